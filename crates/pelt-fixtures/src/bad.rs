//! The bad-input corpus (`fixtures/bad/`): one small valid quad (4 vertices, 2 triangles,
//! POSITION, NORMAL, TEXCOORD_0, COLOR_0, u16 indices) written as GLB, as glTF with a data URI
//! and as glTF with an external `quad.bin`, then broken in one way per file: truncated and
//! lying GLB headers and chunks, JSON errors, buffers, views and accessors that claim more
//! than is there, indices out of range, NaN and infinite attributes, invalid and non-triangle
//! modes, a 4 GiB buffer holding 1 KiB, malformed data URIs, URIs that leave the folder, and
//! OBJ files with bad indices.
//!
//! Each case names the place its error must name (`expected.json`); the test suite checks
//! that every file fails with that place, its own file name, no output and bounded memory.

use serde_json::{Map, Value, json};

/// One corpus file.
pub struct BadCase {
    /// File name inside `fixtures/bad/`.
    pub name: String,
    /// Its bytes.
    pub bytes: Vec<u8>,
    /// What the error must name (a substring of the place).
    pub place: &'static str,
    /// A substring of the message.
    pub message: &'static str,
}

/// The valid quad's binary buffer: positions, normals, UVs, colors (float), u16 indices.
pub fn quad_bin() -> Vec<u8> {
    let mut b = Vec::new();
    let pos = [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    for p in pos {
        p.iter().for_each(|v| b.extend(v.to_le_bytes()));
    }
    for _ in 0..4 {
        [0.0f32, 0.0, 1.0]
            .iter()
            .for_each(|v| b.extend(v.to_le_bytes()));
    }
    for p in pos {
        [p[0], 1.0 - p[1]]
            .iter()
            .for_each(|v| b.extend(v.to_le_bytes()));
    }
    for _ in 0..4 {
        [1.0f32, 0.5, 0.5, 1.0]
            .iter()
            .for_each(|v| b.extend(v.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        b.extend(i.to_le_bytes());
    }
    b.resize(208, 0);
    b
}

/// Byte offsets in [`quad_bin`].
const POS: usize = 0;
const NORMAL: usize = 48;
const UV: usize = 96;
const COLOR: usize = 128;
const INDEX: usize = 192;

/// The valid quad's JSON; buffer 0 has no URI (GLB form).
pub fn quad_json() -> Value {
    json!({
        "asset": {"version": "2.0", "generator": "pelt bad-input corpus"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "quad"}],
        "meshes": [{"name": "quad", "primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2, "COLOR_0": 3},
            "indices": 4,
            "mode": 4
        }]}],
        "buffers": [{"byteLength": 208}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": POS, "byteLength": 48, "target": 34962},
            {"buffer": 0, "byteOffset": NORMAL, "byteLength": 48, "target": 34962},
            {"buffer": 0, "byteOffset": UV, "byteLength": 32, "target": 34962},
            {"buffer": 0, "byteOffset": COLOR, "byteLength": 64, "target": 34962},
            {"buffer": 0, "byteOffset": INDEX, "byteLength": 12, "target": 34963}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC4"},
            {"bufferView": 4, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ]
    })
}

/// GLB bytes from JSON and BIN (both padded; lengths consistent).
pub fn glb(json: &Value, bin: Option<&[u8]>) -> Vec<u8> {
    let mut chunk = Vec::new();
    if let Some(bin) = bin {
        let padded = bin.len().next_multiple_of(4);
        chunk.extend((padded as u32).to_le_bytes());
        chunk.extend(0x004E_4942u32.to_le_bytes());
        chunk.extend(bin);
        chunk.resize(8 + padded, 0);
    }
    crate::mutate::assemble_glb(&serde_json::to_vec(json).unwrap_or_default(), &chunk)
}

/// The quad as a `.gltf` whose buffer is a base64 data URI.
fn gltf_data_uri(json: &Value, bin: &[u8]) -> Value {
    use base64::Engine as _;
    let mut j = json.clone();
    j["buffers"][0]["uri"] = json!(format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(bin)
    ));
    j
}

fn text(v: &Value) -> Vec<u8> {
    let mut t = serde_json::to_vec_pretty(v).unwrap_or_default();
    t.push(b'\n');
    t
}

/// `json` with `edit` applied.
fn edited(edit: impl FnOnce(&mut Value)) -> Value {
    let mut j = quad_json();
    edit(&mut j);
    j
}

/// The quad's BIN with a little-endian word written at `at`.
fn bin_with(at: usize, bytes: &[u8]) -> Vec<u8> {
    let mut b = quad_bin();
    b[at..at + bytes.len()].copy_from_slice(bytes);
    b
}

/// A GLB with a header word (at byte `at`) replaced.
fn glb_word(at: usize, v: u32) -> Vec<u8> {
    let mut g = glb(&quad_json(), Some(&quad_bin()));
    g[at..at + 4].copy_from_slice(&v.to_le_bytes());
    g
}

/// Sets `json[path...] = v` along object keys and array indices.
fn set(j: &mut Value, path: &[&str], v: Value) {
    let mut at = j;
    for p in path {
        at = match p.parse::<usize>() {
            Ok(i) => &mut at[i],
            Err(_) => &mut at[*p],
        };
    }
    *at = v;
}

/// Removes `json[path...][key]`.
fn remove(j: &mut Value, path: &[&str], key: &str) {
    let mut at = j;
    for p in path {
        at = match p.parse::<usize>() {
            Ok(i) => &mut at[i],
            Err(_) => &mut at[*p],
        };
    }
    if let Some(m) = at.as_object_mut() {
        m.remove(key);
    }
}

const PRIM: [&str; 4] = ["meshes", "0", "primitives", "0"];

/// An OBJ triangle list with `faces` appended.
fn obj(faces: &str) -> Vec<u8> {
    format!(
        "# pelt bad-input corpus\nv 0 0 0 1 0.5 0.5\nv 1 0 0 1 0.5 0.5\nv 1 1 0 1 0.5 0.5\n\
         v 0 1 0 1 0.5 0.5\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n{faces}"
    )
    .into_bytes()
}

/// Every corpus file, in a fixed order. `quad.bin` (the valid external buffer some cases
/// point at) is written beside them by [`write`].
pub fn all() -> Vec<BadCase> {
    let bin = quad_bin();
    let good_glb = glb(&quad_json(), Some(&bin));
    let mut cases: Vec<BadCase> = Vec::new();
    let mut add = |name: &str, bytes: Vec<u8>, place: &'static str, message: &'static str| {
        cases.push(BadCase {
            name: name.to_owned(),
            bytes,
            place,
            message,
        });
    };
    let glb_of = |j: Value| glb(&j, Some(&quad_bin()));
    let uri_of = |j: Value| text(&gltf_data_uri(&j, &quad_bin()));
    let ext_of = |j: Value, uri: &str| {
        let mut j = j;
        j["buffers"][0]["uri"] = json!(uri);
        text(&j)
    };

    // GLB container.
    add("glb-empty.glb", Vec::new(), "GLB header", "bad magic");
    add(
        "glb-truncated-header.glb",
        good_glb[..10].to_vec(),
        "GLB header",
        "truncated",
    );
    add(
        "glb-truncated-json.glb",
        good_glb[..60].to_vec(),
        "GLB header",
        "declares",
    );
    add(
        "glb-truncated-bin.glb",
        good_glb[..good_glb.len() - 40].to_vec(),
        "GLB header",
        "declares",
    );
    let mut t = good_glb[..good_glb.len() - 40].to_vec();
    let n = t.len() as u32;
    t[8..12].copy_from_slice(&n.to_le_bytes());
    add(
        "glb-truncated-bin-fixed-length.glb",
        t,
        "GLB chunk 1",
        "declares",
    );
    add(
        "glb-bad-magic.glb",
        [b"glTX", &good_glb[4..]].concat(),
        "GLB header",
        "bad magic",
    );
    add(
        "glb-version-1.glb",
        glb_word(4, 1),
        "GLB header",
        "version 1",
    );
    add(
        "glb-version-3.glb",
        glb_word(4, 3),
        "GLB header",
        "version 3",
    );
    add(
        "glb-length-too-big.glb",
        glb_word(8, good_glb.len() as u32 + 4),
        "GLB header",
        "declares",
    );
    add(
        "glb-length-zero.glb",
        glb_word(8, 0),
        "GLB header",
        "declares",
    );
    add(
        "glb-json-chunk-huge.glb",
        glb_word(12, 0xFFFF_FFF0),
        "GLB chunk 0",
        "declares",
    );
    let json_len = u32::from_le_bytes([good_glb[12], good_glb[13], good_glb[14], good_glb[15]]);
    let bin_at = 20 + json_len as usize;
    add(
        "glb-bin-chunk-huge.glb",
        glb_word(bin_at, 0x7FFF_FFFF),
        "GLB chunk 1",
        "declares",
    );
    add(
        "glb-first-chunk-bin.glb",
        glb_word(16, 0x004E_4942),
        "GLB chunk 0",
        "expected JSON",
    );
    add(
        "glb-second-chunk-unknown.glb",
        glb_word(bin_at + 4, 0x1234_5678),
        "GLB chunk 1",
        "expected BIN",
    );
    let mut h = b"glTF".to_vec();
    h.extend(2u32.to_le_bytes());
    h.extend(12u32.to_le_bytes());
    add("glb-no-chunks.glb", h, "GLB", "no JSON chunk");
    let mut g = good_glb.clone();
    g.extend([1, 0, 0, 0]);
    let n = g.len() as u32;
    g[8..12].copy_from_slice(&n.to_le_bytes());
    add(
        "glb-stray-chunk-header.glb",
        g,
        "GLB chunk",
        "truncated chunk header",
    );
    let mut g = good_glb.clone();
    g[21] = 0xFF;
    add("glb-json-not-utf8.glb", g, "JSON line 1", "");
    add(
        "glb-no-bin-chunk.glb",
        glb(&quad_json(), None),
        "buffers[0]",
        "no GLB BIN chunk",
    );

    // JSON.
    add("json-empty.gltf", Vec::new(), "JSON line 1", "EOF");
    let full = uri_of(quad_json());
    add(
        "json-truncated.gltf",
        full[..full.len() / 2].to_vec(),
        "JSON line",
        "EOF",
    );
    add(
        "json-trailing-comma.gltf",
        br#"{"asset": {"version": "2.0"},}"#.to_vec(),
        "JSON line 1",
        "trailing comma",
    );
    add(
        "json-root-array.gltf",
        b"[1, 2, 3]\n".to_vec(),
        "JSON",
        "root is not an object",
    );
    add(
        "json-binary-noise.gltf",
        (0..=255u8).rev().collect(),
        "JSON line 1",
        "",
    );
    let mut deep = b"{\"asset\": {\"version\": \"2.0\"}, \"extras\": ".to_vec();
    deep.extend(std::iter::repeat_n(b'[', 100_000));
    add(
        "json-deep-nesting.gltf",
        deep,
        "JSON line 1",
        "recursion limit",
    );
    add(
        "json-asset-missing.gltf",
        uri_of(edited(|j| remove(j, &[], "asset"))),
        "asset.version",
        "missing",
    );
    add(
        "json-version-1.gltf",
        uri_of(edited(|j| set(j, &["asset", "version"], json!("1.0")))),
        "asset.version",
        "glTF 1.0",
    );
    add(
        "json-version-number.gltf",
        uri_of(edited(|j| set(j, &["asset", "version"], json!(2.0)))),
        "asset.version",
        "missing",
    );
    add(
        "json-draco-required.gltf",
        uri_of(edited(|j| {
            set(
                j,
                &["extensionsRequired"],
                json!(["KHR_draco_mesh_compression"]),
            )
        })),
        "extensionsRequired",
        "KHR_draco_mesh_compression",
    );

    // Buffers.
    add(
        "buffer-bytelength-missing.glb",
        glb_of(edited(|j| remove(j, &["buffers", "0"], "byteLength"))),
        "buffers[0]",
        "byteLength is missing",
    );
    add(
        "buffer-bytelength-negative.glb",
        glb_of(edited(|j| {
            set(j, &["buffers", "0", "byteLength"], json!(-208))
        })),
        "buffers[0]",
        "byteLength is missing",
    );
    add(
        "buffer-bytelength-larger.glb",
        glb_of(edited(|j| {
            set(j, &["buffers", "0", "byteLength"], json!(4096))
        })),
        "buffers[0]",
        "byteLength is 4096",
    );
    let mut kib = quad_bin();
    kib.resize(1024, 0);
    add(
        "buffer-4gib-declared.glb",
        glb(
            &edited(|j| set(j, &["buffers", "0", "byteLength"], json!(4_294_967_296u64))),
            Some(&kib),
        ),
        "buffers[0]",
        "byteLength is 4294967296, but only 1024",
    );
    add(
        "buffer-4gib-declared-data-uri.gltf",
        {
            let mut j = gltf_data_uri(&quad_json(), &kib);
            j["buffers"][0]["byteLength"] = json!(4_294_967_296u64);
            text(&j)
        },
        "buffers[0]",
        "byteLength is 4294967296, but only 1024",
    );
    add(
        "buffer-second-without-uri.glb",
        glb_of(edited(|j| {
            if let Some(b) = j["buffers"].as_array_mut() {
                b.push(json!({"byteLength": 4}));
            }
        })),
        "buffers[1]",
        "has no uri",
    );
    add(
        "buffer-external-short.gltf",
        ext_of(
            edited(|j| set(j, &["buffers", "0", "byteLength"], json!(4096))),
            "quad.bin",
        ),
        "buffers[0]",
        "byteLength is 4096, but only 208",
    );

    // Data URIs.
    add(
        "datauri-no-comma.gltf",
        ext_of(quad_json(), "data:application/octet-stream;base64"),
        "buffers[0]",
        "no comma",
    );
    add(
        "datauri-not-base64.gltf",
        ext_of(quad_json(), "data:application/octet-stream,AAAA"),
        "buffers[0]",
        "not base64",
    );
    add(
        "datauri-bad-characters.gltf",
        ext_of(quad_json(), "data:application/octet-stream;base64,AA*A$$"),
        "buffers[0]",
        "malformed base64",
    );
    add(
        "datauri-short.gltf",
        ext_of(quad_json(), "data:application/octet-stream;base64,AAAAAAAA"),
        "buffers[0]",
        "byteLength is 208, but only 6",
    );
    add(
        "datauri-image-malformed.gltf",
        uri_of(edited(|j| {
            set(
                j,
                &["images"],
                json!([{"uri": "data:image/png;base64,%%%"}]),
            )
        })),
        "images[0]",
        "malformed base64",
    );

    // URIs that leave the folder, or name nothing.
    for (name, uri, message) in [
        (
            "uri-parent.gltf",
            "../bad/quad.bin",
            "leaves the asset's folder",
        ),
        (
            "uri-nested-parent.gltf",
            "sub/../../quad.bin",
            "leaves the asset's folder",
        ),
        (
            "uri-percent-parent.gltf",
            "%2e%2e/bad/quad.bin",
            "leaves the asset's folder",
        ),
        (
            "uri-backslash-parent.gltf",
            "..\\bad\\quad.bin",
            "leaves the asset's folder",
        ),
        ("uri-absolute.gltf", "/etc/passwd", "absolute path"),
        ("uri-file-scheme.gltf", "file:///etc/passwd", "scheme"),
        ("uri-http.gltf", "http://example.invalid/quad.bin", "scheme"),
        (
            "uri-drive-letter.gltf",
            "C:/quad.bin",
            "scheme or drive letter",
        ),
        (
            "uri-bad-percent.gltf",
            "quad%zz.bin",
            "malformed percent-encoding",
        ),
        ("uri-missing-file.gltf", "missing.bin", "cannot read uri"),
    ] {
        add(name, ext_of(quad_json(), uri), "buffers[0]", message);
    }
    add(
        "uri-image-parent.gltf",
        uri_of(edited(|j| {
            set(j, &["images"], json!([{"uri": "../fur/dots.png"}]))
        })),
        "images[0]",
        "leaves the asset's folder",
    );
    add(
        "uri-image-absolute.gltf",
        uri_of(edited(|j| {
            set(j, &["images"], json!([{"uri": "/dev/zero"}]))
        })),
        "images[0]",
        "absolute path",
    );
    add(
        "image-unknown-type.gltf",
        uri_of(edited(|j| {
            set(j, &["images"], json!([{"uri": "data:;base64,AAAA"}]))
        })),
        "images[0]",
        "unknown image type",
    );

    // Buffer views.
    add(
        "view-out-of-range.glb",
        glb_of(edited(|j| {
            set(j, &["bufferViews", "0", "byteOffset"], json!(200))
        })),
        "bufferViews[0]",
        "exceed buffer 0",
    );
    add(
        "view-length-overflow.glb",
        glb_of(edited(|j| {
            set(j, &["bufferViews", "1", "byteLength"], json!(u64::MAX))
        })),
        "bufferViews[1]",
        "exceed buffer 0",
    );
    add(
        "view-buffer-missing.glb",
        glb_of(edited(|j| {
            set(j, &["bufferViews", "0", "buffer"], json!(5))
        })),
        "bufferViews[0]",
        "buffer 5 does not exist",
    );
    add(
        "view-stride-too-small.glb",
        glb_of(edited(|j| {
            set(j, &["bufferViews", "0", "byteStride"], json!(2))
        })),
        "bufferViews[0]",
        "byteStride 2 is outside",
    );
    add(
        "view-stride-too-large.glb",
        glb_of(edited(|j| {
            set(j, &["bufferViews", "0", "byteStride"], json!(256))
        })),
        "bufferViews[0]",
        "byteStride 256 is outside",
    );
    add(
        "view-missing.glb",
        glb_of(edited(|j| {
            set(j, &["accessors", "0", "bufferView"], json!(99))
        })),
        "POSITION (accessor 0)",
        "bufferView 99 does not exist",
    );

    // Accessors.
    add(
        "accessor-count-lie.glb",
        glb_of(edited(|j| {
            set(j, &["accessors", "0", "count"], json!(1000))
        })),
        "POSITION (accessor 0)",
        "1000 elements",
    );
    add(
        "accessor-count-u32-max.glb",
        glb_of(edited(|j| {
            set(j, &["accessors", "1", "count"], json!(4_294_967_295u64))
        })),
        "NORMAL (accessor 1)",
        "4294967295 elements",
    );
    add(
        "accessor-count-zero.glb",
        glb_of(edited(|j| set(j, &["accessors", "0", "count"], json!(0)))),
        "POSITION (accessor 0)",
        "count is missing or zero",
    );
    add(
        "accessor-count-huge-without-view.glb",
        glb_of(edited(|j| {
            remove(j, &["accessors", "3"], "bufferView");
            set(j, &["accessors", "3", "count"], json!(1u64 << 40));
        })),
        "COLOR_0 (accessor 3)",
        "without a bufferView",
    );
    add(
        "accessor-offset-past-view.glb",
        glb_of(edited(|j| {
            set(j, &["accessors", "2", "byteOffset"], json!(64))
        })),
        "TEXCOORD_0 (accessor 2)",
        "need more",
    );
    add(
        "accessor-offset-misaligned.glb",
        glb_of(edited(|j| {
            set(j, &["accessors", "0", "byteOffset"], json!(2))
        })),
        "POSITION (accessor 0)",
        "not a multiple",
    );
    add(
        "accessor-stride-lie.glb",
        glb_of(edited(|j| {
            set(j, &["bufferViews", "0", "byteStride"], json!(20))
        })),
        "POSITION (accessor 0)",
        "stride 20",
    );
    add(
        "accessor-component-type.glb",
        glb_of(edited(|j| {
            set(j, &["accessors", "0", "componentType"], json!(5127))
        })),
        "POSITION (accessor 0)",
        "componentType",
    );
    add(
        "accessor-type-vec5.glb",
        glb_of(edited(|j| {
            set(j, &["accessors", "0", "type"], json!("VEC5"))
        })),
        "POSITION (accessor 0)",
        "\"VEC5\" is invalid",
    );
    add(
        "accessor-type-mat4.glb",
        glb_of(edited(|j| {
            set(j, &["accessors", "3", "type"], json!("MAT4"))
        })),
        "COLOR_0 (accessor 3)",
        "matrix",
    );
    add(
        "accessor-position-vec2.glb",
        glb_of(edited(|j| {
            set(j, &["accessors", "0", "type"], json!("VEC2"))
        })),
        "POSITION (accessor 0)",
        "expected VEC3",
    );
    add(
        "accessor-missing.glb",
        glb_of(edited(|j| {
            set(
                j,
                &[&PRIM[..], &["attributes", "POSITION"]].concat(),
                json!(42),
            )
        })),
        "POSITION (accessor 42)",
        "does not exist",
    );
    add(
        "accessor-index-string.glb",
        glb_of(edited(|j| {
            set(
                j,
                &[&PRIM[..], &["attributes", "NORMAL"]].concat(),
                json!("1"),
            )
        })),
        "attributes.NORMAL",
        "not an accessor index",
    );
    add(
        "accessor-color-count-mismatch.glb",
        glb_of(edited(|j| set(j, &["accessors", "3", "count"], json!(3)))),
        "COLOR_0",
        "has 3 elements, POSITION has 4",
    );
    add(
        "accessor-sparse-index-out-of-range.glb",
        glb_of(edited(|j| {
            set(
                j,
                &["accessors", "3", "sparse"],
                json!({
                    "count": 1,
                    "indices": {"bufferView": 0, "componentType": 5123, "byteOffset": 14},
                    "values": {"bufferView": 3}
                }),
            )
        })),
        "COLOR_0 (accessor 3) sparse",
        "is 16256: sparse indices must increase and stay below 4",
    );
    add(
        "accessor-sparse-count-too-big.glb",
        glb_of(edited(|j| {
            set(
                j,
                &["accessors", "3", "sparse"],
                json!({
                    "count": 5,
                    "indices": {"bufferView": 4, "componentType": 5123},
                    "values": {"bufferView": 3}
                }),
            )
        })),
        "COLOR_0 (accessor 3) sparse",
        "outside 1..=4",
    );
    add(
        "primitive-no-position.glb",
        glb_of(edited(|j| {
            remove(j, &[&PRIM[..], &["attributes"]].concat(), "POSITION")
        })),
        "meshes[0] \"quad\" primitives[0]",
        "no POSITION",
    );
    add(
        "primitive-not-object.glb",
        glb_of(edited(|j| {
            set(j, &["meshes", "0", "primitives", "0"], json!(7))
        })),
        "meshes[0] \"quad\" primitives[0]",
        "not a JSON object",
    );

    // Indices.
    add(
        "index-out-of-range.glb",
        glb(
            &quad_json(),
            Some(&bin_with(INDEX + 4, &9u16.to_le_bytes())),
        ),
        "meshes[0] \"quad\" primitives[0]",
        "index 2 is 9, but the primitive has only 4 vertices",
    );
    add(
        "index-u16-max.glb",
        glb(
            &quad_json(),
            Some(&bin_with(INDEX + 10, &u16::MAX.to_le_bytes())),
        ),
        "meshes[0] \"quad\" primitives[0]",
        "index 5 is 65535",
    );
    add(
        "index-float-type.glb",
        glb_of(edited(|j| {
            set(j, &["accessors", "4", "componentType"], json!(5126))
        })),
        "indices",
        "",
    );
    add(
        "index-normalized.glb",
        glb_of(edited(|j| {
            set(j, &["accessors", "4", "normalized"], json!(true))
        })),
        "indices (accessor 4)",
        "SCALAR unsigned",
    );
    add(
        "index-count-not-triangles.glb",
        glb_of(edited(|j| set(j, &["accessors", "4", "count"], json!(5)))),
        "meshes[0] \"quad\" primitives[0]",
        "not a whole number of triangles",
    );
    add(
        "index-accessor-string.glb",
        glb_of(edited(|j| {
            set(j, &[&PRIM[..], &["indices"]].concat(), json!("4"))
        })),
        "indices",
        "not an accessor index",
    );

    // Non-finite attributes.
    let nan = f32::NAN.to_le_bytes();
    let inf = f32::INFINITY.to_le_bytes();
    add(
        "nan-position.glb",
        glb(&quad_json(), Some(&bin_with(POS + 16, &nan))),
        "meshes[0] \"quad\" primitives[0]",
        "vertex 1",
    );
    add(
        "inf-position.glb",
        glb(&quad_json(), Some(&bin_with(POS + 36, &inf))),
        "meshes[0] \"quad\" primitives[0]",
        "vertex 3",
    );
    add(
        "nan-normal.glb",
        glb(&quad_json(), Some(&bin_with(NORMAL + 24, &nan))),
        "meshes[0] \"quad\" primitives[0]",
        "vertex 2",
    );
    add(
        "inf-texcoord.glb",
        glb(
            &quad_json(),
            Some(&bin_with(UV, &(-f32::INFINITY).to_le_bytes())),
        ),
        "meshes[0] \"quad\" primitives[0]",
        "vertex 0",
    );
    add(
        "nan-color.glb",
        glb(&quad_json(), Some(&bin_with(COLOR + 60, &nan))),
        "meshes[0] \"quad\" primitives[0]",
        "vertex 3",
    );
    add(
        "nan-color-data-uri.gltf",
        text(&gltf_data_uri(&quad_json(), &bin_with(COLOR + 4, &nan))),
        "meshes[0] \"quad\" primitives[0]",
        "vertex 0",
    );

    // Modes.
    add(
        "mode-7.glb",
        glb_of(edited(|j| {
            set(j, &[&PRIM[..], &["mode"]].concat(), json!(7))
        })),
        "primitives[0] mode",
        "invalid mode 7",
    );
    add(
        "mode-negative.glb",
        glb_of(edited(|j| {
            set(j, &[&PRIM[..], &["mode"]].concat(), json!(-1))
        })),
        "primitives[0] mode",
        "invalid mode -1",
    );
    add(
        "mode-string.glb",
        glb_of(edited(|j| {
            set(j, &[&PRIM[..], &["mode"]].concat(), json!("4"))
        })),
        "primitives[0] mode",
        "invalid mode",
    );
    for (name, mode) in [
        ("mode-points-only.glb", 0),
        ("mode-lines-only.glb", 1),
        ("mode-line-strip-only.glb", 3),
    ] {
        add(
            name,
            glb_of(edited(|j| {
                set(j, &[&PRIM[..], &["mode"]].concat(), json!(mode))
            })),
            "meshes",
            "nothing to bake",
        );
    }
    add(
        "meshes-missing.gltf",
        uri_of(edited(|j| {
            remove(j, &[], "meshes");
            remove(j, &["nodes", "0"], "mesh");
        })),
        "meshes",
        "nothing to bake",
    );

    // Schema and validator rules in parts a bake passes through untouched.
    type Case = (&'static str, fn(&mut Value), &'static str, &'static str);
    let schema: [Case; 13] = [
        (
            "schema-name-number.glb",
            |j| set(j, &["meshes", "0", "name"], json!(5)),
            "meshes[0].name",
            "invalid type: integer `5`, expected a string",
        ),
        (
            "schema-extensions-number.glb",
            |j| set(j, &["nodes", "0", "extensions"], json!(5)),
            "nodes[0].extensions",
            "does not follow the glTF 2.0 schema",
        ),
        (
            "schema-extension-data-number.glb",
            |j| {
                set(j, &["nodes", "0", "extensions"], json!({"EXT_x": 5}));
                set(j, &["extensionsUsed"], json!(["EXT_x"]));
            },
            "nodes[0].extensions.EXT_x",
            "an extension's data must be a JSON object",
        ),
        (
            "schema-extension-undeclared.glb",
            |j| set(j, &["nodes", "0", "extensions"], json!({"EXT_x": {}})),
            "extensionsUsed",
            "EXT_x is used but not declared",
        ),
        (
            "schema-index-negative.glb",
            |j| set(j, &["scenes", "0", "nodes"], json!([-1])),
            "scenes[0].nodes[0]",
            "invalid type: integer `-1`",
        ),
        (
            "schema-texcoord-1-without-0.glb",
            |j| {
                remove(j, &PRIM[..], "attributes");
                set(
                    j,
                    &[&PRIM[..], &["attributes"]].concat(),
                    json!({"POSITION": 0, "NORMAL": 1, "TEXCOORD_1": 2, "COLOR_0": 3}),
                );
            },
            "meshes[0].primitives[0].attributes",
            "TEXCOORD_n attributes must be numbered from 0 without gaps",
        ),
        (
            "schema-matrix-and-trs.glb",
            |j| {
                set(
                    j,
                    &["nodes", "0", "matrix"],
                    json!([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]),
                );
                set(j, &["nodes", "0", "scale"], json!([2, 2, 2]));
            },
            "nodes[0].matrix",
            "either a matrix or translation/rotation/scale",
        ),
        (
            "schema-rotation-not-unit.glb",
            |j| set(j, &["nodes", "0", "rotation"], json!([0, 0, 0, 0.5])),
            "nodes[0].rotation",
            "not a unit quaternion",
        ),
        (
            "schema-emissive-above-1.glb",
            |j| {
                set(j, &["materials"], json!([{"emissiveFactor": [2, 0, 0]}]));
                set(j, &[&PRIM[..], &["material"]].concat(), json!(0));
            },
            "materials[0].emissiveFactor",
            "2 is outside [0, 1]",
        ),
        (
            "schema-weights-without-targets.glb",
            |j| set(j, &["meshes", "0", "weights"], json!([0.5])),
            "meshes[0].weights",
            "1 weights for 0 morph targets",
        ),
        (
            "schema-texcoord-missing-for-texture.glb",
            |j| {
                set(j, &["samplers"], json!([{}]));
                set(
                    j,
                    &["images"],
                    json!([{"uri": "data:image/png;base64,iVBORw0KGgo="}]),
                );
                set(j, &["textures"], json!([{"source": 0, "sampler": 0}]));
                set(
                    j,
                    &["materials"],
                    json!([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "texCoord": 1}}}]),
                );
                set(j, &[&PRIM[..], &["material"]].concat(), json!(0));
            },
            "meshes[0].primitives[0].material",
            "reads TEXCOORD_1, which the primitive does not have",
        ),
        (
            "schema-empty-array.glb",
            |j| set(j, &["nodes", "0", "children"], json!([])),
            "nodes[0].children",
            "an array must not be empty",
        ),
        (
            "schema-min-version-above-version.glb",
            |j| set(j, &["asset", "minVersion"], json!("2.1")),
            "asset.minVersion",
            "minVersion 2.1 is above version 2.0",
        ),
    ];
    for (name, edit, place, message) in schema {
        add(name, glb_of(edited(edit)), place, message);
    }
    add(
        "schema-color-above-1.glb",
        glb(
            &quad_json(),
            Some(&bin_with(COLOR + 4, &2.0f32.to_le_bytes())),
        ),
        "meshes[0].primitives[0].attributes.COLOR_0",
        "element 0 holds 2, outside [0, 1]",
    );

    // OBJ.
    add(
        "obj-index-past-end.obj",
        obj("f 1 2 9\n"),
        "OBJ line 10",
        "position index 9 is outside 1..=4",
    );
    add(
        "obj-index-zero.obj",
        obj("f 0 1 2\n"),
        "OBJ line 10",
        "position index 0",
    );
    add(
        "obj-negative-too-far.obj",
        obj("f -1 -2 -9\n"),
        "OBJ line 10",
        "index -9 reaches before the first of the 4",
    );
    add(
        "obj-negative-before-vertices.obj",
        b"f -1 -2 -3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n".to_vec(),
        "OBJ line 1",
        "index -1 reaches before the first of the 0",
    );
    add(
        "obj-index-not-number.obj",
        obj("f 1 2 x\n"),
        "OBJ line 10",
        "\"x\" is not an integer",
    );
    add(
        "obj-texcoord-index-bad.obj",
        obj("f 1/1 2/2 3/7\n"),
        "OBJ line 10",
        "texture coordinate index 7",
    );
    add(
        "obj-normal-index-bad.obj",
        obj("f 1//1 2//1 3//2\n"),
        "OBJ line 10",
        "normal index 2",
    );
    add(
        "obj-index-overflow.obj",
        obj("f 1 2 99999999999999999999\n"),
        "OBJ line 10",
        "not an integer",
    );
    add("obj-no-faces.obj", obj(""), "OBJ", "no faces");
    add("obj-empty.obj", Vec::new(), "OBJ", "no faces");
    add(
        "obj-nan-position.obj",
        b"v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".to_vec(),
        "meshes[0] \"unnamed_object\" primitives[0]",
        "POSITION: vertex 0 has a non-finite value",
    );
    add(
        "obj-inf-position.obj",
        b"v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n".to_vec(),
        "meshes[0] \"unnamed_object\" primitives[0]",
        "POSITION: vertex 1 has a non-finite value",
    );
    // Bytes that are not UTF-8 are decoded lossily, as peers do; noise still holds no faces.
    add(
        "obj-binary-noise.obj",
        (0..=255u8).cycle().take(1024).collect(),
        "OBJ",
        "no faces",
    );
    cases
}

/// Writes the corpus, `quad.bin` and `expected.json` into `out`.
pub fn write(out: &std::path::Path) -> std::io::Result<usize> {
    std::fs::create_dir_all(out)?;
    std::fs::write(out.join("quad.bin"), quad_bin())?;
    let mut expected = Map::new();
    let cases = all();
    for c in &cases {
        std::fs::write(out.join(&c.name), &c.bytes)?;
        expected.insert(
            c.name.clone(),
            json!({"place": c.place, "message": c.message}),
        );
    }
    let mut t = serde_json::to_vec_pretty(&Value::Object(expected)).unwrap_or_default();
    t.push(b'\n');
    std::fs::write(out.join("expected.json"), t)?;
    Ok(cases.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corpus_names_are_unique_and_at_least_60() {
        let cases = all();
        let names: std::collections::BTreeSet<&str> =
            cases.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names.len(), cases.len(), "duplicate names");
        assert!(cases.len() >= 60, "{} cases", cases.len());
    }

    #[test]
    fn the_base_quad_is_a_consistent_glb() {
        let g = glb(&quad_json(), Some(&quad_bin()));
        let (json, bin) = crate::mutate::glb_chunks(&g).expect("consistent lengths");
        assert!(serde_json::from_slice::<Value>(&g[json]).is_ok());
        assert_eq!(bin.map(|r| r.len()), Some(208));
    }
}
