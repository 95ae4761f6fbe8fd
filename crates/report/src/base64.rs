//! Base64 (RFC 4648, standard alphabet, padded), for the `.glb` embedded in the page.

const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/// `data` in base64, appended to `out`. Encoded into bytes, then appended as one string (the
/// page of a 10,000-body run embeds tens of megabytes; a `char` push per symbol was three times
/// slower).
pub fn encode_into(data: &[u8], out: &mut String) {
    let mut bytes = Vec::with_capacity(data.len().div_ceil(3) * 4);
    let sym = |n: u32, k: u32| ALPHABET[((n >> (18 - 6 * k)) & 63) as usize];
    let chunks = data.chunks_exact(3);
    let rest = chunks.remainder();
    for c in chunks {
        let n = (u32::from(c[0]) << 16) | (u32::from(c[1]) << 8) | u32::from(c[2]);
        bytes.extend_from_slice(&[sym(n, 0), sym(n, 1), sym(n, 2), sym(n, 3)]);
    }
    if let [first, more @ ..] = rest {
        let second = more.first().copied().unwrap_or(0);
        let n = (u32::from(*first) << 16) | (u32::from(second) << 8);
        let third = if more.is_empty() { b'=' } else { sym(n, 2) };
        bytes.extend_from_slice(&[sym(n, 0), sym(n, 1), third, b'=']);
    }
    // The alphabet is ASCII, so the bytes are valid UTF-8 (the lossy branch never runs).
    match std::str::from_utf8(&bytes) {
        Ok(text) => out.push_str(text),
        Err(_) => out.push_str(&String::from_utf8_lossy(&bytes)),
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn rfc4648_vectors() {
        for (plain, coded) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            let mut s = String::new();
            super::encode_into(plain.as_bytes(), &mut s);
            assert_eq!(s, coded);
        }
    }

    /// Every byte value in every position of a chunk, against a bit-by-bit encoding.
    #[test]
    fn all_bytes_in_all_positions() {
        let data: Vec<u8> = (0..=255u8).chain((0..=255u8).rev()).chain([7, 9]).collect();
        for len in [data.len(), data.len() - 1, data.len() - 2] {
            let bits: String = data[..len].iter().map(|b| format!("{b:08b}")).collect();
            let mut expected = String::new();
            for six in bits.as_bytes().chunks(6) {
                let mut v = 0usize;
                for (k, &bit) in six.iter().enumerate() {
                    v |= usize::from(bit - b'0') << (5 - k);
                }
                expected.push(char::from(super::ALPHABET[v]));
            }
            while !expected.len().is_multiple_of(4) {
                expected.push('=');
            }
            let mut s = String::from("prefix:");
            super::encode_into(&data[..len], &mut s);
            assert_eq!(s, format!("prefix:{expected}"), "length {len}");
        }
    }
}
