//! OBJ files as peers write them (`fixtures/obj/`): materials in `.mtl` files with textures
//! (`map_Kd`, `map_Bump` with options), an empty and a missing `.mtl`, Latin-1 names and UTF-16
//! text with a byte-order mark. Every file is written from here, byte for byte.

use std::path::Path;

/// A painted 2×2 grid in the XZ plane facing +Y, `v x y z r g b` (comb +X, length 1), with
/// texture coordinates and normals; `usemtl` lines go where `materials` says (face index →
/// name).
fn grid(header: &str, materials: &[(usize, &str)]) -> String {
    let mut s = String::from(header);
    for z in 0..3 {
        for x in 0..3 {
            s += &format!("v {x} 0 {z} 1 0.5 0.5\n");
        }
    }
    for z in 0..3 {
        for x in 0..3 {
            s += &format!("vt {} {}\n", x as f32 / 2.0, 1.0 - z as f32 / 2.0);
        }
    }
    s += "vn 0 1 0\n";
    for (f, (x, z)) in (0..2).flat_map(|z| (0..2).map(move |x| (x, z))).enumerate() {
        if let Some((_, name)) = materials.iter().find(|(at, _)| *at == f) {
            s += &format!("usemtl {name}\n");
        }
        let v = |dx: usize, dz: usize| {
            let i = (z + dz) * 3 + x + dx + 1;
            format!("{i}/{i}/1")
        };
        s += &format!("f {} {} {} {}\n", v(0, 0), v(0, 1), v(1, 1), v(1, 0));
    }
    s
}

/// An 8×8 PNG: a red and blue checker, or the flat tangent-space normal.
fn png(checker: bool) -> Vec<u8> {
    let img = image::RgbImage::from_fn(8, 8, |x, y| {
        if !checker {
            image::Rgb([128, 128, 255])
        } else if (x / 2 + y / 2) % 2 == 0 {
            image::Rgb([220, 30, 30])
        } else {
            image::Rgb([30, 30, 220])
        }
    });
    let mut out = std::io::Cursor::new(Vec::new());
    // Writing to memory cannot fail for a valid image.
    let _ = img.write_to(&mut out, image::ImageFormat::Png);
    out.into_inner()
}

/// Every file, by path under `fixtures/obj/`.
pub fn all() -> Vec<(&'static str, Vec<u8>)> {
    let textured_mtl = "# Written by pelt-fixtures.\n\
        newmtl fur\nKd 0.8 0.8 0.8\nNs 250\nmap_Kd -s 1 1 1 tex/albedo.png\n\
        map_Bump -bm 0.5 tex/normal.png\n\n\
        newmtl skin\nKd 0.9 0.5 0.4\nd 0.5\nPr 0.25\n";
    // Latin-1 bytes (é = 0xE9) in a comment and a material name, written as a placeholder
    // byte first.
    let latin1: Vec<u8> = grid(
        "# Latin-1 names, as older Windows exporters write them: caf\u{1}\nmtllib latin1.mtl\n",
        &[(0, "caf\u{1}")],
    )
    .into_bytes()
    .into_iter()
    .map(|b| if b == 1 { 0xE9 } else { b })
    .collect();
    let utf16: Vec<u8> = [0xFF, 0xFE]
        .into_iter()
        .chain(
            grid("# UTF-16 with a byte-order mark\n", &[])
                .encode_utf16()
                .flat_map(u16::to_le_bytes),
        )
        .collect();
    vec![
        (
            "textured.obj",
            grid("mtllib textured.mtl\n", &[(0, "fur"), (2, "skin")]).into_bytes(),
        ),
        ("textured.mtl", textured_mtl.as_bytes().to_vec()),
        ("tex/albedo.png", png(true)),
        ("tex/normal.png", png(false)),
        (
            "empty-mtl.obj",
            grid("mtllib empty.mtl\n", &[(0, "fur")]).into_bytes(),
        ),
        ("empty.mtl", Vec::new()),
        (
            "missing-mtl.obj",
            grid("mtllib not-here.mtl\n", &[(0, "fur")]).into_bytes(),
        ),
        ("latin1.obj", latin1),
        ("latin1.mtl", b"newmtl caf\xE9\nKd 0.2 0.6 0.2\n".to_vec()),
        ("utf16.obj", utf16),
    ]
}

/// Writes [`all`] under `dir`.
pub fn write(dir: &Path) -> std::io::Result<()> {
    for (rel, bytes) in all() {
        let path = dir.join(rel);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)?;
        }
        std::fs::write(path, bytes)?;
    }
    Ok(())
}
