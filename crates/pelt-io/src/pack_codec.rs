//! meshoptimizer's encoders for compressed output (`EXT_meshopt_compression`): the vertex
//! codec at format version 0 (the one the extension defines), the triangle index codec, and
//! the octahedral and exponential filters with their decoders, over plain byte slices.
//! [`crate::pack`] decides what goes through them.

use meshopt::ffi;

/// One bufferView's compressed stream and how to decode it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Packed {
    /// `ATTRIBUTES` or `TRIANGLES`.
    pub mode: &'static str,
    /// The filter a reader applies after decoding.
    pub filter: Option<Filter>,
    /// Bytes per element.
    pub stride: usize,
    /// Elements.
    pub count: usize,
    /// The compressed bytes.
    pub stream: Vec<u8>,
}

/// A filter the extension defines, applied before the vertex codec.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Filter {
    /// Unit vectors as two octahedral coordinates (normals, tangents; w kept).
    Octahedral,
    /// Floats as a shared exponent and an integer mantissa.
    Exponential,
}

impl Filter {
    /// The name the extension's JSON uses.
    pub fn name(self) -> &'static str {
        match self {
            Filter::Octahedral => "OCTAHEDRAL",
            Filter::Exponential => "EXPONENTIAL",
        }
    }
}

/// `data` (`count` elements of `stride` bytes) through the vertex codec, format version 0.
#[expect(
    unsafe_code,
    reason = "meshoptimizer's encoder is C; it reads count × stride bytes of the source slice and writes at most the bound it reports into a buffer of that size"
)]
pub fn encode_vertices(data: &[u8], stride: usize) -> Vec<u8> {
    let count = data.len() / stride;
    let bound = unsafe { ffi::meshopt_encodeVertexBufferBound(count, stride) };
    let mut out = vec![0u8; bound];
    // Level 2 is the default; version 0 is what EXT_meshopt_compression decoders read.
    let n = unsafe {
        ffi::meshopt_encodeVertexBufferLevel(
            out.as_mut_ptr(),
            out.len(),
            data.as_ptr().cast(),
            count,
            stride,
            2,
            0,
        )
    };
    out.truncate(n);
    out
}

/// Unit vectors given as xyzw floats (w kept: a tangent's handedness) filtered to `bits`-bit
/// octahedral coordinates in `stride` bytes (4: signed bytes, 8: signed shorts).
#[expect(
    unsafe_code,
    reason = "meshoptimizer's filter is C; it reads 4 floats per element and writes count × stride bytes into a buffer of exactly that size"
)]
pub fn encode_octahedral(xyzw: &[[f32; 4]], stride: usize, bits: i32) -> Vec<u8> {
    let mut out = vec![0u8; xyzw.len() * stride];
    unsafe {
        ffi::meshopt_encodeFilterOct(
            out.as_mut_ptr().cast(),
            xyzw.len(),
            stride,
            bits,
            xyzw.as_flattened().as_ptr(),
        );
    }
    out
}

/// Float vectors (`stride / 4` components each) with an exponent shared by each component
/// across all elements and a `bits`-bit mantissa: a fixed-point grid per component that
/// decodes to floats.
#[expect(
    unsafe_code,
    reason = "meshoptimizer's filter is C; it reads stride / 4 floats per element and writes count × stride bytes into a buffer of exactly that size"
)]
pub fn encode_exponential(floats: &[f32], stride: usize, bits: i32) -> Vec<u8> {
    let count = floats.len() * 4 / stride;
    let mut out = vec![0u8; count * stride];
    unsafe {
        ffi::meshopt_encodeFilterExp(
            out.as_mut_ptr().cast(),
            count,
            stride,
            bits,
            floats.as_ptr(),
            ffi::meshopt_EncodeExpMode_meshopt_EncodeExpSharedComponent,
        );
    }
    out
}

/// What a reader gets back from filtered bytes: the filter's decoder run on a copy.
#[expect(
    unsafe_code,
    reason = "meshoptimizer's filter decoders are C and work in place on count × stride bytes, exactly the copy's length"
)]
pub fn unfilter(filter: Filter, encoded: &[u8], stride: usize) -> Vec<u8> {
    let mut out = encoded.to_vec();
    let count = out.len() / stride;
    let dst = out.as_mut_ptr().cast();
    unsafe {
        match filter {
            Filter::Octahedral => ffi::meshopt_decodeFilterOct(dst, count, stride),
            Filter::Exponential => ffi::meshopt_decodeFilterExp(dst, count, stride),
        }
    }
    out
}

/// For each vertex, its place in first-use order over `indices` (`u32::MAX`: unused).
/// meshoptimizer's `optimizeVertexFetchRemap`, called directly: the crate's wrapper cuts the
/// table to the number of used vertices, which loses entries when some are unused.
#[expect(
    unsafe_code,
    reason = "meshoptimizer's remap is C; it reads the index slice (every index checked below vertex_count first) and writes vertex_count entries into a table of exactly that size"
)]
pub fn fetch_remap(indices: &[u32], vertex_count: usize) -> Option<Vec<u32>> {
    if indices.iter().any(|&i| i as usize >= vertex_count) {
        return None;
    }
    let mut remap = vec![u32::MAX; vertex_count];
    unsafe {
        ffi::meshopt_optimizeVertexFetchRemap(
            remap.as_mut_ptr(),
            indices.as_ptr(),
            indices.len(),
            vertex_count,
        );
    }
    Some(remap)
}

/// A triangle list through the index codec and back: the stream and the indices a reader
/// decodes, which hold the same triangles in the same order, each possibly rotated (winding
/// kept). None if the codec fails.
pub fn encode_triangles(indices: &[u32], vertex_count: usize) -> Option<(Vec<u8>, Vec<u32>)> {
    let stream = meshopt::encode_index_buffer(indices, vertex_count).ok()?;
    let decoded = meshopt::decode_index_buffer::<u32>(&stream, indices.len()).ok()?;
    Some((stream, decoded))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertices_round_trip_through_the_decoder() {
        let data: Vec<u8> = (0..4000u32).flat_map(|i| (i * 7).to_le_bytes()).collect();
        let stream = encode_vertices(&data, 8);
        assert!(stream.len() < data.len() / 2, "{} bytes", stream.len());
        assert_eq!(stream[0], 0xa0, "format version 0");
        let back: Vec<[u8; 8]> =
            meshopt::decode_vertex_buffer(&stream, data.len() / 8).expect("decodes");
        assert_eq!(back.as_flattened(), &data[..]);
    }

    #[test]
    fn octahedral_keeps_direction_and_handedness() {
        let t = [[0.6, 0.0, 0.8, -1.0], [0.0, -1.0, 0.0, 1.0]];
        let back = unfilter(Filter::Octahedral, &encode_octahedral(&t, 4, 8), 4);
        for (k, v) in t.iter().enumerate() {
            let q: Vec<f32> = (0..4)
                .map(|c| f32::from(back[4 * k + c] as i8) / 127.0)
                .collect();
            for c in 0..3 {
                assert!((q[c] - v[c]).abs() < 0.02, "{q:?} vs {v:?}");
            }
            assert_eq!(q[3], v[3]);
        }
    }

    #[test]
    fn triangles_keep_order_and_winding() {
        let idx = [0, 1, 2, 2, 1, 3, 3, 1, 4, 4, 5, 3];
        let (_, back) = encode_triangles(&idx, 6).expect("encodes");
        for (a, b) in idx.chunks(3).zip(back.chunks(3)) {
            let rotations = [[a[0], a[1], a[2]], [a[1], a[2], a[0]], [a[2], a[0], a[1]]];
            assert!(rotations.contains(&[b[0], b[1], b[2]]), "{a:?} → {b:?}");
        }
    }
}
