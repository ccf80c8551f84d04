//! Seeded mutations of valid or invalid inputs, for the bad-input corpus and the fuzz harness:
//! bit flips, byte stamps, truncations, splices of two files, edits of JSON (or OBJ) number
//! tokens, and stamps of awkward 32-bit values (NaN, infinities, huge indices) into a GLB's
//! BIN chunk. A GLB whose JSON chunk was edited gets its chunk and file lengths fixed up, so
//! the mutation reaches the parser behind the header checks.
//!
//! Everything is a pure function of the seed: case `i` of seed `s` is the same bytes on every
//! machine, so a crash is reproduced by its (seed, case) alone.

/// SplitMix64: small, fast, and good enough to pick mutations.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator for `seed`.
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (0 when `n` is 0).
    pub fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next_u64() % n as u64) as usize
        }
    }

    /// One of `items`.
    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// The kinds of mutation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Flip 1 to 8 random bits.
    BitFlip,
    /// Set 1 to 4 random bytes to 0x00, 0xFF, 0x7F or 0x80.
    ByteStamp,
    /// Cut the file at a random length.
    Truncate,
    /// A prefix of this file followed by a suffix of another.
    Splice,
    /// Replace a number token of the JSON (or OBJ text) with an edge value.
    Number,
    /// Write a NaN, an infinity or a huge integer at an aligned offset of a GLB's BIN chunk.
    BinWord,
}

/// All kinds, in the order [`mutate`] weighs them.
pub const KINDS: [Kind; 6] = [
    Kind::BitFlip,
    Kind::ByteStamp,
    Kind::Truncate,
    Kind::Splice,
    Kind::Number,
    Kind::BinWord,
];

/// Values a number token is replaced with: zero, negatives, the edges of u32 and of f64's
/// exact integers, huge and tiny floats, fractions where integers belong, and non-numbers.
const NUMBER_EDITS: &[&str] = &[
    "0",
    "-1",
    "1",
    "3",
    "5",
    "7",
    "255",
    "65535",
    "2147483647",
    "2147483648",
    "4294967295",
    "4294967296",
    "9007199254740993",
    "18446744073709551615",
    "1e308",
    "-1e308",
    "1e-320",
    "0.5",
    "-0.0",
    "null",
    "\"4\"",
    "[]",
    "{}",
    "true",
];

/// 32-bit words stamped into binary data.
const WORDS: &[u32] = &[
    0x7FC0_0000, // NaN
    0x7F80_0000, // +Inf
    0xFF80_0000, // -Inf
    0xFFFF_FFFF, // u32::MAX, a NaN as f32
    0x8000_0000, // -0.0, i32::MIN
    0x0000_FFFF,
    0x0001_0000,
    0x7F7F_FFFF, // f32::MAX
    0x0000_0001, // the smallest subnormal
];

/// Mutates `input` once with a kind drawn from `rng`; `other` is the splice partner.
pub fn mutate(rng: &mut Rng, input: &[u8], other: &[u8]) -> (Kind, Vec<u8>) {
    // Number edits reach the deepest code: weigh them double.
    let kind = match rng.below(KINDS.len() + 1) {
        i if i < KINDS.len() => KINDS[i],
        _ => Kind::Number,
    };
    (kind, apply(kind, rng, input, other))
}

/// Applies one mutation of `kind`.
pub fn apply(kind: Kind, rng: &mut Rng, input: &[u8], other: &[u8]) -> Vec<u8> {
    let mut b = input.to_vec();
    match kind {
        Kind::BitFlip => {
            for _ in 0..1 + rng.below(8) {
                if !b.is_empty() {
                    let i = rng.below(b.len());
                    b[i] ^= 1 << rng.below(8);
                }
            }
        }
        Kind::ByteStamp => {
            for _ in 0..1 + rng.below(4) {
                if !b.is_empty() {
                    let i = rng.below(b.len());
                    b[i] = *rng.pick(&[0x00, 0xFF, 0x7F, 0x80]);
                }
            }
        }
        Kind::Truncate => {
            let n = rng.below(b.len());
            b.truncate(n);
        }
        Kind::Splice => {
            let cut = rng.below(b.len() + 1);
            let from = rng.below(other.len() + 1);
            b.truncate(cut);
            b.extend_from_slice(&other[from..]);
        }
        Kind::Number => b = edit_number(rng, input),
        Kind::BinWord => match glb_chunks(input) {
            Some((_, Some(bin))) if bin.len() >= 4 => {
                for _ in 0..1 + rng.below(3) {
                    let at = bin.start + 4 * rng.below(bin.len() / 4);
                    b[at..at + 4].copy_from_slice(&rng.pick(WORDS).to_le_bytes());
                }
            }
            _ => b = edit_number(rng, input),
        },
    }
    b
}

/// Replaces one number token of the text (a GLB's JSON chunk, else the whole file) with an
/// edge value, or nudges it by ±1 or doubles it. GLB lengths are fixed up afterwards.
fn edit_number(rng: &mut Rng, input: &[u8]) -> Vec<u8> {
    let (text, glb) = match glb_chunks(input) {
        Some((json, _)) => (&input[json.clone()], Some(json)),
        None => (input, None),
    };
    let tokens = number_tokens(text);
    if tokens.is_empty() {
        return input.to_vec();
    }
    let tok = tokens[rng.below(tokens.len())].clone();
    let old = std::str::from_utf8(&text[tok.clone()]).unwrap_or("0");
    let new = match rng.below(4) {
        0 => match old.parse::<i64>() {
            Ok(v) => (v + if rng.below(2) == 0 { 1 } else { -1 }).to_string(),
            Err(_) => "0".to_owned(),
        },
        1 => match old.parse::<f64>() {
            Ok(v) => format!("{}", v * 2.0),
            Err(_) => "1".to_owned(),
        },
        _ => (*rng.pick(NUMBER_EDITS)).to_owned(),
    };
    let mut edited = text[..tok.start].to_vec();
    edited.extend_from_slice(new.as_bytes());
    edited.extend_from_slice(&text[tok.end..]);
    match glb {
        Some(json) => rebuild_glb(input, json, &edited),
        None => edited,
    }
}

/// Byte ranges of the number tokens of a JSON or OBJ text (digits with sign, point, exponent).
pub fn number_tokens(text: &[u8]) -> Vec<std::ops::Range<usize>> {
    let mut out = Vec::new();
    let mut i = 0;
    let mut in_string = false;
    while i < text.len() {
        let c = text[i];
        if c == b'"' && (i == 0 || text[i - 1] != b'\\') {
            in_string = !in_string;
            i += 1;
            continue;
        }
        let starts = !in_string
            && (c.is_ascii_digit()
                || (c == b'-' && text.get(i + 1).is_some_and(u8::is_ascii_digit)))
            && (i == 0 || !(text[i - 1].is_ascii_alphanumeric() || text[i - 1] == b'_'));
        if starts {
            let start = i;
            i += 1;
            while i < text.len()
                && (text[i].is_ascii_digit() || matches!(text[i], b'.' | b'e' | b'E' | b'+' | b'-'))
            {
                i += 1;
            }
            out.push(start..i);
        } else {
            i += 1;
        }
    }
    out
}

/// A GLB's JSON chunk data range and BIN chunk data range, when the header and chunk lengths
/// are consistent.
pub fn glb_chunks(b: &[u8]) -> Option<(std::ops::Range<usize>, Option<std::ops::Range<usize>>)> {
    let word = |o: usize| -> Option<usize> {
        let s = b.get(o..o + 4)?;
        Some(u32::from_le_bytes([s[0], s[1], s[2], s[3]]) as usize)
    };
    if !b.starts_with(b"glTF") || word(8)? != b.len() {
        return None;
    }
    let json_len = word(12)?;
    let json = 20..20usize.checked_add(json_len)?;
    if json.end > b.len() || word(16)? != 0x4E4F_534A {
        return None;
    }
    let bin = match (word(json.end), word(json.end + 4)) {
        (Some(len), Some(0x004E_4942)) => {
            let r = json.end + 8..json.end + 8 + len;
            (r.end <= b.len()).then_some(r)
        }
        _ => None,
    };
    Some((json, bin))
}

/// The GLB `b` with its JSON chunk data replaced by `json`, every length fixed up, and the
/// rest of the file kept.
fn rebuild_glb(b: &[u8], old: std::ops::Range<usize>, json: &[u8]) -> Vec<u8> {
    assemble_glb(json, &b[old.end..])
}

/// A GLB of a JSON chunk holding `json` (space-padded to 4 bytes) followed by `rest` (further
/// chunks, headers included, taken as they are), with the header's total length consistent.
pub fn assemble_glb(json: &[u8], rest: &[u8]) -> Vec<u8> {
    let padded = json.len().next_multiple_of(4);
    let total = 20 + padded + rest.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(padded as u32).to_le_bytes());
    out.extend_from_slice(&0x4E4F_534Au32.to_le_bytes());
    out.extend_from_slice(json);
    out.resize(20 + padded, b' ');
    out.extend_from_slice(rest);
    out
}

/// Case `case` of `seed` over `seeds` (name, bytes): the seed file chosen, the kind of the
/// last mutation, and the mutated bytes (one mutation, or two or three stacked in a quarter
/// of the cases).
pub fn case(seeds: &[(String, Vec<u8>)], seed: u64, case: u64) -> (&str, Kind, Vec<u8>) {
    let mut rng = Rng::new(seed ^ case.wrapping_mul(0xD6E8_FEB8_6659_FD93));
    let (name, bytes) = &seeds[rng.below(seeds.len())];
    let other = &seeds[rng.below(seeds.len())].1;
    let (mut kind, mut out) = mutate(&mut rng, bytes, other);
    let extra = if rng.below(4) == 0 {
        1 + rng.below(2)
    } else {
        0
    };
    for _ in 0..extra {
        (kind, out) = mutate(&mut rng, &out, other);
    }
    (name, kind, out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn number_tokens_skip_strings_and_names() {
        let t = br#"{"a1": 12, "b": [-3.5e2, 0], "s": "7", "TEXCOORD_0": 4}"#;
        let got: Vec<&[u8]> = number_tokens(t).into_iter().map(|r| &t[r]).collect();
        assert_eq!(got, vec![&b"12"[..], b"-3.5e2", b"0", b"4"]);
    }

    #[test]
    fn json_edits_of_a_glb_keep_its_lengths_consistent() {
        let json = br#"{"asset":{"version":"2.0"},"x":[1,2,3]}"#;
        let glb = rebuild_glb(
            &[b"glTF".as_slice(), &[0; 16], json].concat(),
            20..20 + json.len(),
            json,
        );
        assert!(glb_chunks(&glb).is_some());
        let mut rng = Rng::new(5);
        let mut changed = 0;
        for _ in 0..50 {
            let e = edit_number(&mut rng, &glb);
            let (j, _) = glb_chunks(&e).expect("lengths fixed up");
            changed += usize::from(e[j] != glb[20..]);
        }
        // An edit may write the value that was there ("1" for 1): rarely.
        assert!(changed >= 40, "only {changed} of 50 edits changed the JSON");
    }

    #[test]
    fn cases_are_a_function_of_seed_and_index() {
        let seeds = vec![
            ("a".to_owned(), b"{\"n\": [1, 2, 3]}".to_vec()),
            ("b".to_owned(), vec![7u8; 64]),
        ];
        for i in 0..20 {
            assert_eq!(case(&seeds, 9, i).2, case(&seeds, 9, i).2);
        }
        let distinct: std::collections::HashSet<Vec<u8>> =
            (0..20).map(|i| case(&seeds, 9, i).2).collect();
        assert!(
            distinct.len() > 10,
            "only {} distinct cases",
            distinct.len()
        );
    }
}
