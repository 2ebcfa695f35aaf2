//! The resource location a host hands to `fmi2Instantiate` (FMI 2.0, section 2.1.5: a URI, in
//! practice a `file:` URI, RFC 8089) as a path of the platform the binary runs on.
//!
//! Windows hosts write the drive letter into the path (`file:///C:/Users/x/resources`), and
//! UNC shares as the URI's host (`file://server/share/x`) or with four slashes
//! (`file:////server/share/x`); Unix hosts write `file:///tmp/x`, some `file:/tmp/x` or
//! `file://localhost/tmp/x`. Before, every form became a Unix path, so on Windows
//! `file:///C:/...` was looked up as `/C:/...` and a tailored FMU missed its `scene.toml`.

use std::path::PathBuf;

/// The path of the resource location `uri` on this platform; None when it is not a `file:` URI
/// (or is not valid UTF-8 once decoded).
pub fn resource_path(uri: &str) -> Option<PathBuf> {
    file_uri_to_path(uri, cfg!(windows)).map(PathBuf::from)
}

/// The path a `file:` URI names, percent-decoded, for Windows (`windows`, with `\` separators)
/// or for a Unix system.
/// - `file:///p`, `file:/p`, `file://localhost/p`: the local path `/p`; on Windows a leading
///   drive (`/C:/x`, also the old `/C|/x`) loses its slash: `C:\x`.
/// - `file://server/share/x`, `file:////server/share/x`: on Windows the UNC path
///   `\\server\share\x`. A Unix system has no UNC paths; there the host part is read as the
///   first folder of the path, as before (`file://tmp/x` is `/tmp/x`).
pub fn file_uri_to_path(uri: &str, windows: bool) -> Option<String> {
    let scheme = uri.get(..5)?;
    if !scheme.eq_ignore_ascii_case("file:") {
        return None;
    }
    let rest = &uri[5..];
    let path = match rest.strip_prefix("//") {
        Some(after) => {
            let (host, path) = after.split_at(after.find('/').unwrap_or(after.len()));
            if host.is_empty() || host.eq_ignore_ascii_case("localhost") {
                path.to_string()
            } else if windows {
                format!("//{host}{path}")
            } else {
                format!("/{host}{path}")
            }
        }
        None => rest.to_string(),
    };
    let decoded = percent_decode(&path)?;
    if !windows {
        return Some(if decoded.starts_with('/') {
            decoded
        } else {
            format!("/{decoded}")
        });
    }
    let b = decoded.as_bytes();
    let drive =
        |i: usize| b.len() > i + 1 && b[i].is_ascii_alphabetic() && matches!(b[i + 1], b':' | b'|');
    let local = if b.first() == Some(&b'/') && drive(1) {
        format!("{}:{}", &decoded[1..2], &decoded[3..])
    } else if drive(0) {
        format!("{}:{}", &decoded[..1], &decoded[2..])
    } else {
        decoded
    };
    Some(local.replace('/', "\\"))
}

/// `%XX` escapes decoded; None when the result is not UTF-8.
fn percent_decode(s: &str) -> Option<String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%'
            && i + 2 < bytes.len()
            && let Some(b) = std::str::from_utf8(&bytes[i + 1..i + 3])
                .ok()
                .and_then(|h| u8::from_str_radix(h, 16).ok())
        {
            out.push(b);
            i += 3;
            continue;
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8(out).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unix(u: &str) -> Option<String> {
        file_uri_to_path(u, false)
    }
    fn win(u: &str) -> Option<String> {
        file_uri_to_path(u, true)
    }

    #[test]
    fn unix_locations() {
        assert_eq!(
            unix("file:///tmp/a%20b/resources").as_deref(),
            Some("/tmp/a b/resources")
        );
        assert_eq!(unix("file:/tmp/x").as_deref(), Some("/tmp/x"));
        assert_eq!(unix("file://localhost/tmp/x").as_deref(), Some("/tmp/x"));
        assert_eq!(unix("FILE:///tmp/x").as_deref(), Some("/tmp/x"));
        assert_eq!(unix("file://tmp/x").as_deref(), Some("/tmp/x"));
        assert_eq!(unix("http://example/x"), None);
        assert_eq!(unix("file:///tmp/%ff"), None, "not UTF-8");
        assert_eq!(unix("file:///tmp/100%"), Some("/tmp/100%".into()));
    }

    #[test]
    fn windows_drive_letters() {
        let want = Some(r"C:\Users\a b\x.fmu\resources".to_string());
        assert_eq!(win("file:///C:/Users/a%20b/x.fmu/resources"), want);
        assert_eq!(win("file:/C:/Users/a%20b/x.fmu/resources"), want);
        assert_eq!(win("file://localhost/C:/Users/a%20b/x.fmu/resources"), want);
        assert_eq!(win("file://LOCALHOST/C:/Users/a%20b/x.fmu/resources"), want);
        assert_eq!(win("file:///C|/Users/a%20b/x.fmu/resources"), want);
        assert_eq!(win("file:C:/Users/a%20b/x.fmu/resources"), want);
        assert_eq!(win("file:///z:/tmp/r").as_deref(), Some(r"z:\tmp\r"));
        assert_eq!(win("file:///C:/").as_deref(), Some(r"C:\"));
        // what the Unix rule made of them: a path under the root of the current drive
        assert_eq!(unix("file:///C:/x").as_deref(), Some("/C:/x"));
    }

    #[test]
    fn windows_unc_shares() {
        let want = Some(r"\\server\share\sim\x.fmu\resources".to_string());
        assert_eq!(win("file://server/share/sim/x.fmu/resources"), want);
        assert_eq!(win("file:////server/share/sim/x.fmu/resources"), want);
        assert_eq!(
            win("file://server/share/a%20b").as_deref(),
            Some(r"\\server\share\a b")
        );
    }

    #[test]
    fn windows_paths_without_a_drive() {
        // a rooted path on the current drive, as a Unix host under Wine would pass it
        assert_eq!(
            win("file:///tmp/x/resources").as_deref(),
            Some(r"\tmp\x\resources")
        );
        assert_eq!(win("http://example/x"), None);
    }
}
