//! Lists every `.wgsl` file of the repository's `shaders/` folder for `shaders::FILES`, so a
//! feature's new shader is compiled in (and validated, and hot-reloaded) without being named
//! in Rust anywhere but its feature's descriptor.

use std::fmt::Write as _;
use std::path::PathBuf;

fn main() {
    let manifest = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let dir = manifest.join("../../shaders");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .expect("the shaders/ folder beside the crates")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".wgsl"))
        .collect();
    names.sort();
    let mut out = format!(
        "/// Every file in `shaders/`, by name (listed by build.rs).\npub const FILES: [(&str, &str); {}] = [\n",
        names.len()
    );
    for n in &names {
        let path = dir.join(n);
        println!("cargo:rerun-if-changed={}", path.display());
        let _ = writeln!(
            out,
            "    ({n:?}, include_str!({:?})),",
            path.display().to_string()
        );
    }
    out.push_str("];\n");
    let dest =
        PathBuf::from(std::env::var_os("OUT_DIR").expect("set by cargo")).join("shader_files.rs");
    std::fs::write(dest, out).expect("OUT_DIR is writable");
}
