"""pelt's build rules: `pelt_bake` (one furred .glb from one painted mesh) and `pelt_textures`
(the fur texture set of a bake config). See docs/pipelines.md.

Every file an action may read is a declared input, so the actions run in Bazel's sandbox and on
any Remote Execution API service; pelt's outputs are byte-identical on every machine, so a shared
cache serves them to everyone. The tool is `@pelt_tool//:pelt` unless `tool` names another
(`pelt_binary` in repositories.bzl makes that repository); its bytes are an input of every
action, so a new pelt re-runs every bake.
"""

def _input_list(ctx, name, files):
    """Writes the execution-root paths of `files`, one per line, for bake.sh."""
    out = ctx.actions.declare_file(name)
    ctx.actions.write(out, "".join([f.path + "\n" for f in files]))
    return out

def _pelt_bake_impl(ctx):
    out = ctx.actions.declare_file(ctx.label.name + ".glb")
    dep = ctx.actions.declare_file(ctx.label.name + ".glb.d")
    unused = ctx.actions.declare_file(ctx.label.name + ".unused")
    inputs = [ctx.file.src] + ctx.files.srcs
    if ctx.file.config:
        inputs.append(ctx.file.config)
    declared = _input_list(ctx, ctx.label.name + ".inputs", inputs)
    args = ctx.actions.args()
    args.add(ctx.executable.tool)
    args.add_all([out, dep, unused, declared])
    args.add(ctx.file.src)
    if ctx.file.config:
        args.add("--config", ctx.file.config)
    args.add_all(ctx.attr.args)
    ctx.actions.run(
        executable = ctx.executable._wrapper,
        arguments = [args],
        inputs = inputs + [declared],
        tools = [ctx.executable.tool],
        outputs = [out, dep, unused],
        unused_inputs_list = unused,
        mnemonic = "PeltBake",
        progress_message = "Baking %s" % ctx.file.src.short_path,
    )
    return [DefaultInfo(files = depset([out]))]

_TOOL = attr.label(
    default = "@pelt_tool//:pelt",
    executable = True,
    cfg = "exec",
    allow_single_file = True,
    doc = "The pelt executable (default: the pelt_binary repository named pelt_tool).",
)

pelt_bake = rule(
    implementation = _pelt_bake_impl,
    doc = "Bakes `src` with `pelt bake` into `<name>.glb`.",
    attrs = {
        "src": attr.label(
            mandatory = True,
            allow_single_file = [".gltf", ".glb", ".obj"],
            doc = "The painted mesh: .gltf, .glb or .obj.",
        ),
        "srcs": attr.label_list(
            allow_files = True,
            doc = "Files `src` may refer to: .bin buffers, images, .mtl files. Those the bake " +
                  "does not read are pruned from the action's key after its first run.",
        ),
        "config": attr.label(
            allow_single_file = [".json"],
            doc = "A bake config (pelt bake --config).",
        ),
        "args": attr.string_list(
            doc = "More `pelt bake` flags, e.g. [\"--compress\"]. Paths in them are not " +
                  "declared inputs: pass files through `config`.",
        ),
        "tool": _TOOL,
        "_wrapper": attr.label(
            default = "//:bake.sh",
            executable = True,
            cfg = "exec",
            allow_single_file = True,
        ),
    },
)

def _pelt_textures_impl(ctx):
    out = ctx.actions.declare_directory(ctx.label.name)
    args = ctx.actions.args()
    args.add("textures")
    args.add("-q")
    if ctx.file.config:
        args.add("--config", ctx.file.config)
    args.add_all(ctx.attr.args)
    args.add("-o", out.path)
    ctx.actions.run(
        executable = ctx.executable.tool,
        arguments = [args],
        inputs = [ctx.file.config] if ctx.file.config else [],
        outputs = [out],
        mnemonic = "PeltTextures",
        progress_message = "Generating fur textures %s" % ctx.label,
    )
    return [DefaultInfo(files = depset([out]))]

pelt_textures = rule(
    implementation = _pelt_textures_impl,
    doc = "Generates the fur texture set (`pelt textures`) into the directory `<name>`.",
    attrs = {
        "config": attr.label(
            allow_single_file = [".json"],
            doc = "A bake config whose `fur` section gives the texture settings.",
        ),
        "args": attr.string_list(doc = "More `pelt textures` flags, e.g. [\"--seed\", \"7\"]."),
        "tool": _TOOL,
    },
)
