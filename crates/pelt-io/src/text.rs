//! Text files as peers read them (OBJ and MTL): UTF-8 with or without a byte-order mark,
//! UTF-16 (little or big endian) with one, and anything else decoded lossily (each byte that is
//! not UTF-8 becomes U+FFFD) with a warning naming the first such line and byte.

/// Decodes `bytes`; a warning, when the text was repaired, goes to `warnings`.
pub fn decode(label: &str, bytes: &[u8], warnings: &mut Vec<String>) -> String {
    if let Some(rest) = bytes.strip_prefix(&[0xEF, 0xBB, 0xBF]) {
        return utf8(label, rest, warnings);
    }
    let utf16 = match bytes {
        [0xFF, 0xFE, rest @ ..] => Some((rest, u16::from_le_bytes as fn([u8; 2]) -> u16)),
        [0xFE, 0xFF, rest @ ..] => Some((rest, u16::from_be_bytes as fn([u8; 2]) -> u16)),
        _ => None,
    };
    if let Some((rest, unit)) = utf16 {
        let units = rest.chunks_exact(2).map(|c| unit([c[0], c[1]]));
        let text: String = char::decode_utf16(units)
            .map(|c| c.unwrap_or(char::REPLACEMENT_CHARACTER))
            .collect();
        if text.contains(char::REPLACEMENT_CHARACTER) || rest.len() % 2 == 1 {
            warnings.push(format!(
                "{}UTF-16 text with unpaired surrogates or an odd byte count: decoded lossily",
                prefix(label)
            ));
        }
        return text;
    }
    utf8(label, bytes, warnings)
}

fn utf8(label: &str, bytes: &[u8], warnings: &mut Vec<String>) -> String {
    match std::str::from_utf8(bytes) {
        Ok(text) => text.to_owned(),
        Err(e) => {
            let at = e.valid_up_to();
            let line = bytes[..at].iter().filter(|&&b| b == b'\n').count() + 1;
            let column = at
                - bytes[..at]
                    .iter()
                    .rposition(|&b| b == b'\n')
                    .map_or(0, |p| p + 1);
            warnings.push(format!(
                "{}line {line}: not UTF-8 (byte 0x{:02X} at column {}): such bytes were \
                 decoded as U+FFFD",
                prefix(label),
                bytes[at],
                column + 1
            ));
            String::from_utf8_lossy(bytes).into_owned()
        }
    }
}

fn prefix(label: &str) -> String {
    if label.is_empty() {
        String::new()
    } else {
        format!("{label} ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_encoding_peers_read() {
        let p = "";
        let mut w = Vec::new();
        assert_eq!(decode(p, b"\xEF\xBB\xBFv 1 2 3", &mut w), "v 1 2 3");
        let le: Vec<u8> = [0xFF, 0xFE]
            .into_iter()
            .chain("v é".encode_utf16().flat_map(u16::to_le_bytes))
            .collect();
        assert_eq!(decode(p, &le, &mut w), "v é");
        let be: Vec<u8> = [0xFE, 0xFF]
            .into_iter()
            .chain("o x".encode_utf16().flat_map(u16::to_be_bytes))
            .collect();
        assert_eq!(decode(p, &be, &mut w), "o x");
        assert!(w.is_empty(), "{w:?}");
        let latin1 = decode(p, b"v 0 0 0\nusemtl caf\xE9\n", &mut w);
        assert_eq!(latin1, "v 0 0 0\nusemtl caf\u{FFFD}\n");
        assert_eq!(
            w,
            ["line 2: not UTF-8 (byte 0xE9 at column 11): such bytes were decoded as U+FFFD"]
        );
    }
}
