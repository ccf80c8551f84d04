"""`pelt_binary`: a repository exposing an installed pelt as `@<name>//:pelt`.

The executable is copied into the repository, so the bytes Bazel hashes into every action key
are the bytes that run. It is found from `path`, else the `PELT` environment variable, else
`PATH`; the repository is made again when `path`, `PELT` or `PATH` changes, or on
`bazel sync --configure` (run that after reinstalling pelt at the same path).
"""

def _pelt_binary_impl(rctx):
    path = rctx.attr.path or rctx.os.environ.get("PELT", "")
    if path:
        found = rctx.path(path)
    else:
        found = rctx.which("pelt")
        if found == None:
            fail("pelt_binary(name = \"%s\"): no pelt: set path, the PELT environment " % rctx.name +
                 "variable, or put pelt on PATH")
    if not found.exists:
        fail("pelt_binary(name = \"%s\"): %s does not exist" % (rctx.name, found))
    result = rctx.execute(["cp", str(found), "pelt"])
    if result.return_code != 0:
        fail("pelt_binary: cannot copy %s: %s" % (found, result.stderr))
    rctx.execute(["chmod", "+x", "pelt"])
    rctx.file("BUILD.bazel", "\n".join([
        "# pelt, copied from %s by pelt_binary." % found,
        "exports_files([\"pelt\"])",
        "",
    ]))

pelt_binary = repository_rule(
    implementation = _pelt_binary_impl,
    doc = "Exposes an installed pelt as `@<name>//:pelt`.",
    attrs = {
        "path": attr.string(doc = "Absolute path of the pelt executable (default: $PELT, then PATH)."),
    },
    environ = ["PELT", "PATH"],
    configure = True,
    local = True,
)
