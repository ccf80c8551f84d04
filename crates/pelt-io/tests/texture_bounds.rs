//! Textures within bounds: an image larger than the side bound is halved while it decodes (a
//! PNG row by row, a JPEG by its inverse DCT, each with a peak of at most twice the size used,
//! measured with a counting allocator); a header that lies about its size is a refusal naming the image.

use std::path::Path;

use pelt_io::Document;
use pelt_io::picture::decode_within;
use serde_json::json;

#[global_allocator]
static GLOBAL: pelt_alloc::Counting = pelt_alloc::Counting;

/// The counters are the process's: tests that measure take turns.
static MEASURING: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn measuring() -> std::sync::MutexGuard<'static, ()> {
    MEASURING
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// A gradient: red follows x, green follows y (16-bit steps folded to bytes), alpha 255.
fn pixel(x: u32, y: u32, side: u32) -> [u8; 4] {
    [
        (x * 255 / (side - 1)) as u8,
        (y * 255 / (side - 1)) as u8,
        7,
        255,
    ]
}

fn png_bytes(side: u32) -> Vec<u8> {
    let mut out = Vec::new();
    let mut e = png::Encoder::new(&mut out, side, side);
    e.set_color(png::ColorType::Rgba);
    e.set_depth(png::BitDepth::Eight);
    let mut w = e.write_header().expect("header");
    let mut data = Vec::with_capacity((side * side * 4) as usize);
    for y in 0..side {
        for x in 0..side {
            data.extend_from_slice(&pixel(x, y, side));
        }
    }
    w.write_image_data(&data).expect("data");
    drop(w);
    out
}

fn jpeg_bytes(side: u32) -> Vec<u8> {
    let mut img = image::RgbImage::new(side, side);
    for (x, y, p) in img.enumerate_pixels_mut() {
        let [r, g, b, _] = pixel(x, y, side);
        *p = image::Rgb([r, g, b]);
    }
    let mut out = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut out, 95)
        .encode_image(&img)
        .expect("jpeg");
    out
}

/// A document whose only image is `bytes` (in a bufferView).
fn doc_with_image(bytes: Vec<u8>, mime: &str) -> Document {
    let len = bytes.len();
    let serde_json::Value::Object(j) = json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": len}],
        "bufferViews": [{"buffer": 0, "byteLength": len}],
        "images": [{"bufferView": 0, "mimeType": mime}]
    }) else {
        unreachable!("object literal")
    };
    Document::from_parts(Path::new("big.glb"), j, vec![bytes])
}

#[test]
fn a_png_larger_than_the_bound_is_halved_while_it_decodes() {
    let _turn = measuring();
    let side = 4096;
    let doc = doc_with_image(png_bytes(side), "image/png");
    let base = pelt_alloc::reset_peak();
    let (img, stored) = decode_within(&doc, 0, 1024).expect("decodes");
    let peak = pelt_alloc::peak() - base;
    assert_eq!(stored, Some((side, side)));
    assert_eq!((img.width, img.height), (1024, 1024));
    let used = img.pixels.len();
    eprintln!(
        "peak {peak} bytes for {used} bytes decoded ({:.2}×)",
        peak as f64 / used as f64
    );
    assert!(peak <= 2 * used, "peak {peak} > 2 × {used}");
    // Each pixel is the average of its 4 × 4 block: red and green at the block's centre.
    for (x, y) in [(0, 0), (511, 300), (1023, 1023)] {
        let p = &img.pixels[(y * 1024 + x) * 4..][..4];
        let centre = |v: usize| (v * 4) as f64 + 1.5;
        let want = |c: f64| c * 255.0 / f64::from(side - 1);
        assert!(
            (f64::from(p[0]) - want(centre(x))).abs() <= 1.0,
            "{x},{y}: {p:?}"
        );
        assert!(
            (f64::from(p[1]) - want(centre(y))).abs() <= 1.0,
            "{x},{y}: {p:?}"
        );
        assert_eq!((p[2], p[3]), (7, 255));
    }
    // Within the bound it decodes as stored, the peak still within 2×.
    let base = pelt_alloc::reset_peak();
    let (full, stored) = decode_within(&doc, 0, 4096).expect("decodes");
    let peak = pelt_alloc::peak() - base;
    assert_eq!((stored, full.width), (None, side));
    assert!(peak <= 2 * full.pixels.len(), "stored size: peak {peak}");
}

#[test]
fn a_jpeg_is_scaled_by_its_inverse_dct() {
    let _turn = measuring();
    let side = 2048;
    let doc = doc_with_image(jpeg_bytes(side), "image/jpeg");
    let measure = |bound: u32| {
        let base = pelt_alloc::reset_peak();
        let (img, stored) = decode_within(&doc, 0, bound).expect("decodes");
        let ratio = pelt_alloc::peak().saturating_sub(base) as f64 / img.pixels.len() as f64;
        eprintln!("JPEG {side} → {bound}: peak {ratio:.2}× the decoded size");
        assert_eq!(stored, (bound < side).then_some((side, side)));
        assert_eq!((img.width, img.height), (bound, bound));
        // A baseline JPEG: the component planes and the RGB result at the scaled size, then
        // the RGBA result (jpeg-decoder's rayon worker decodes each row as it arrives).
        assert!(ratio <= 2.0, "JPEG {side} → {bound}: peak {ratio:.2}× > 2×");
        img
    };
    // Scaled by 1/2, 1/4 and 1/8 in the inverse DCT, and decoded as stored.
    for bound in [2048, 1024, 512] {
        measure(bound);
    }
    let img = measure(256);
    let p = &img.pixels[(128 * 256 + 64) * 4..][..4];
    // Block centre (64·8 + 3.5, 128·8 + 3.5) of the 2048 gradient; JPEG is lossy.
    assert!(
        (f64::from(p[0]) - 515.5 * 255.0 / 2047.0).abs() <= 4.0,
        "{p:?}"
    );
    assert!(
        (f64::from(p[1]) - 1027.5 * 255.0 / 2047.0).abs() <= 4.0,
        "{p:?}"
    );
}

#[test]
fn a_header_that_lies_about_its_size_is_refused_naming_the_image() {
    let _turn = measuring();
    let mut bytes = png_bytes(512);
    // Keep the header and the first part of the image data: the rows run out.
    bytes.truncate(bytes.len() / 3);
    let doc = doc_with_image(bytes, "image/png");
    for bound in [128, 4096] {
        let err = decode_within(&doc, 0, bound)
            .expect_err("truncated")
            .to_string();
        assert!(
            err.contains("big.glb")
                && err.contains("images[0]")
                && err.contains("cannot be decoded"),
            "{bound}: {err}"
        );
    }
}
