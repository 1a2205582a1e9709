//! A scene file carried in a link: its text deflated and written in base64url (RFC 4648
//! §5, no padding), so that it fits in a link's fragment (after `#`, which a browser
//! never sends to a server) and reads back byte for byte.

/// The longest link the lab writes (characters): longer links are cut or refused by
/// some browsers, mail programs and chat tools, so a scene that needs more is saved as
/// a file instead.
pub const MAX_LINK: usize = 8 * 1024;

/// The most text a carried scene may unpack to (bytes): far more than any scene file
/// that packs into [`MAX_LINK`], and a bound on what a hostile link can make the page
/// allocate.
pub const MAX_UNPACKED: usize = 1 << 20;

/// The 64 characters of base64url, in value order.
const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_";

/// `text` deflated (best compression) and written in base64url.
#[must_use]
pub fn pack(text: &str) -> String {
    base64url(&miniz_oxide::deflate::compress_to_vec(text.as_bytes(), 10))
}

/// What [`pack`] wrote, read back; a one-line reason for anything else.
pub fn unpack(packed: &str) -> Result<String, String> {
    let bytes = from_base64url(packed)?;
    let text = miniz_oxide::inflate::decompress_to_vec_with_limit(&bytes, MAX_UNPACKED).map_err(|e| {
        use miniz_oxide::inflate::TINFLStatus;
        if e.status == TINFLStatus::HasMoreOutput {
            format!("the scene file in the link unpacks to more than {} KB", MAX_UNPACKED / 1024)
        } else {
            "the scene file in the link is damaged (it does not unpack); copy the whole link".to_string()
        }
    })?;
    String::from_utf8(text).map_err(|_| "the scene file in the link is not UTF-8 text".to_string())
}

/// `bytes` in base64url, without padding.
fn base64url(bytes: &[u8]) -> String {
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let word = chunk.iter().enumerate().fold(0u32, |word, (k, &b)| word | u32::from(b) << (16 - 8 * k));
        // 3 bytes give 4 characters, 2 give 3, 1 gives 2.
        for k in 0..=chunk.len() {
            out.push(char::from(ALPHABET[(word >> (18 - 6 * k) & 63) as usize]));
        }
    }
    out
}

/// The bytes a base64url text (without padding) stands for.
fn from_base64url(text: &str) -> Result<Vec<u8>, String> {
    let value = |c: u8| -> Result<u32, String> {
        ALPHABET.iter().position(|&a| a == c).map(|v| v as u32).ok_or_else(|| {
            format!("the scene file in the link has a character '{}' that base64url has not", char::from(c))
        })
    };
    if text.len() % 4 == 1 {
        return Err("the scene file in the link is cut short; copy the whole link".into());
    }
    let mut out = Vec::with_capacity(text.len() / 4 * 3 + 2);
    for chunk in text.as_bytes().chunks(4) {
        let mut word = 0u32;
        for (k, &c) in chunk.iter().enumerate() {
            word |= value(c)? << (18 - 6 * k);
        }
        for k in 0..chunk.len() - 1 {
            out.push((word >> (16 - 8 * k)) as u8);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// RFC 4648's test vectors (§10), in the URL-safe alphabet without padding.
    #[test]
    fn base64url_matches_the_rfcs_vectors() {
        for (plain, coded) in [
            ("", ""),
            ("f", "Zg"),
            ("fo", "Zm8"),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg"),
            ("fooba", "Zm9vYmE"),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64url(plain.as_bytes()), coded);
            assert_eq!(from_base64url(coded).unwrap(), plain.as_bytes());
        }
        // The two characters that differ from plain base64.
        assert_eq!(base64url(&[0xfb, 0xff]), "-_8");
        assert_eq!(from_base64url("-_8").unwrap(), [0xfb, 0xff]);
    }

    #[test]
    fn every_byte_value_survives_the_round_trip() {
        let bytes: Vec<u8> = (0..=255).chain((0..=255).rev()).collect();
        for cut in 0..bytes.len() {
            assert_eq!(from_base64url(&base64url(&bytes[..cut])).unwrap(), &bytes[..cut]);
        }
    }

    #[test]
    fn every_shipped_scene_file_packs_and_unpacks_to_the_same_text_and_fits_a_link() {
        for name in ["chain", "cloth", "platform", "blob"] {
            let path =
                std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("assets/scenes/{name}.toml"));
            let text = std::fs::read_to_string(path).unwrap();
            let packed = pack(&text);
            assert_eq!(unpack(&packed).unwrap(), text, "{name}");
            assert!(packed.len() < text.len(), "{name}: packing did not shrink it");
            assert!(packed.len() < MAX_LINK, "{name}: {} characters", packed.len());
        }
    }

    #[test]
    fn a_damaged_link_is_one_line_not_a_panic() {
        let packed = pack("[scene]\nname = \"x\"\n");
        assert!(unpack(&packed[..packed.len() - 4]).unwrap_err().contains("damaged"));
        assert!(unpack("a").unwrap_err().contains("cut short"));
        assert!(unpack("ab+d").unwrap_err().contains("'+'"));
        assert!(unpack(&base64url(&[0xff, 0xfe, 0x00])).is_err());
        // Not UTF-8 inside.
        let latin = miniz_oxide::deflate::compress_to_vec(&[0xe9, 0x20, 0xff], 6);
        assert!(unpack(&base64url(&latin)).unwrap_err().contains("UTF-8"));
    }

    #[test]
    fn a_bomb_is_refused_within_its_bound() {
        let huge = "#".repeat(MAX_UNPACKED + 1);
        let packed = pack(&huge);
        assert!(packed.len() < MAX_LINK, "a bomb small enough for a link");
        assert!(unpack(&packed).unwrap_err().contains("more than 1024 KB"));
        assert_eq!(unpack(&pack(&huge[1..])).unwrap().len(), MAX_UNPACKED);
    }
}
