# pelt's everyday commands (https://github.com/casey/just).

# Build everything (release).
build:
    cargo build --release --workspace

# Run every test (the README's test command).
test:
    cargo test --workspace

# The main job on bundled data: bake the fixture creature with fur and render it
# (out/demo: creature.glb, demo.png, turntable.png).
demo:
    cargo run --release -- demo

# Bake the creature fixture and print its report.
bake:
    cargo run --release -- bake fixtures/creature.glb -o out/creature.glb --report -

# Bake every fixture and check the outputs with the Khronos glTF-Validator.
validate:
    bash tools/validate-fixtures.sh

# Regenerate the committed fixtures (and the bad-input corpus, fixtures/bad).
fixtures:
    cargo run --release -p pelt-fixtures --bin gen-fixtures -- fixtures

# Benchmark the 1.3 M-triangle bakes against gltfpack and glTF-Transform (20 interleaved rounds).
bench runs="20":
    bash bench/compare.sh {{runs}}

# Per-triangle cost of the default bake at 10 k to 1.3 M triangles.
bench-scaling runs="15":
    cargo build --release -q -p pelt -p pelt-fixtures
    python3 bench/scaling.py {{runs}}

# Batch bake: 64 files at --jobs 1 and 2, --incremental, one process per file.
bench-batch runs="5":
    bash bench/batch.sh {{runs}}

# Fuzz the loaders and the bake for SECONDS (release build; failing inputs in target/fuzz-crashes).
fuzz seconds="600" seed="1":
    cargo run --release -p pelt-fuzz -- --seconds {{seconds}} --seed {{seed}}

# Lints and formatting.
lint:
    cargo fmt --all -- --check
    cargo clippy --workspace --all-targets

# Topology benchmark (normal groups, IDs, fin edges) at 10 k, 100 k and 1.3 M triangles.
bench-topology:
    cargo bench --bench topology

# Fur textures with the example config's strand model (out/fur: PNGs and fur.json).
textures:
    cargo run --release -- textures --config fixtures/fur.json -o out/fur

# Fur texture benchmark (512², 1024², 2048² sets).
bench-textures:
    cargo bench -p pelt-fur --bench textures

# Render the example scene (out/showcase.png) and explain its passes.
render:
    cargo run --release -- render fixtures/scenes/showcase.json --explain -o out/showcase.png

# The inferred-lighting paper's two experiments and the fur experiment, on a back end.
bench-render backend="vulkan":
    cargo run --release -- render-bench --backend {{backend}}

# Mirrors and glass against the ray tracer: steps, min-max, cube size, layers, bounces.
bench-reflections backend="vulkan":
    cargo run --release -- render-bench --experiment reflections --backend {{backend}} --frames 9 --warmup 2 --pictures docs/reflections

# Frame time against shell count, fins, stipple against WBOIT, forward (demo scene).
bench-fur backend="vulkan":
    cargo run --release -- render-bench --experiment fur --backend {{backend}}
    PELT_BACKEND={{backend}} cargo bench -p pelt-preview --bench lbuffer_scale

# The strand reference's time on small and extreme inputs (160x90): docs/reference.md's table.
bench-strands:
    cargo build --release
    bash bench/strands.sh

# The demo creature in a window (bakes it first): orbit, knobs on keys, reload on change.
view: demo
    cargo run --release -- view out/demo/creature.glb

# pelt view's frame budget: orbit frame times at 66, 100 and 200 ms budgets under Xvfb.
bench-view frames="30":
    bash bench/view.sh {{frames}}

# The speed/accuracy trade on the demo scene (640×360, Vulkan): every knob against its
# reference, then the tables and pictures docs/sweep.md quotes copied into docs/sweep.
sweep-demo backend="vulkan":
    cargo run --release -- demo --size 640x360 -q
    cargo run --release -- sweep out/demo/scene.json --backend {{backend}} -o out/sweep
    mkdir -p docs/sweep
    cp out/sweep/sweep.md out/sweep/sweep.csv out/sweep/sweep.json out/sweep/sweep.png out/sweep/contact.png out/sweep/reference-strands.png docs/sweep/
    cp out/sweep/images/shells=16.png docs/sweep/default.png
    cp out/sweep/heat/shells=16.png docs/sweep/default-flip.png
