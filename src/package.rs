//! The packager: writes an `.fmu` (a zip archive) with the layout of FMI 2.0, section 2.3.
//!
//! Entries are written in a fixed order with a fixed time stamp and fixed permissions, so the
//! same inputs give a byte-identical archive.

use std::io::Write;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, DateTime, ZipWriter};

/// Everything that goes into one FMU.
#[derive(Clone, Debug, Default)]
pub struct FmuContents {
    /// `modelIdentifier`: names the binary `binaries/linux64/<id>.so`.
    pub identifier: String,
    pub model_description: String,
    /// The shared library built for linux64.
    pub binary: Vec<u8>,
    /// Files of `documentation/` (index.html first, then figures), by file name.
    pub documentation: Vec<(String, Vec<u8>)>,
    /// The `model.png` icon.
    pub icon: Vec<u8>,
    /// Files of `resources/`, by relative path.
    pub resources: Vec<(String, Vec<u8>)>,
}

impl FmuContents {
    /// The archive's entries: (path, bytes, executable).
    fn entries(&self) -> Vec<(String, &[u8], bool)> {
        let mut e: Vec<(String, &[u8], bool)> = vec![
            (
                "modelDescription.xml".into(),
                self.model_description.as_bytes(),
                false,
            ),
            (
                format!("binaries/linux64/{}.so", self.identifier),
                &self.binary,
                true,
            ),
        ];
        e.extend(
            self.documentation
                .iter()
                .map(|(n, b)| (format!("documentation/{n}"), b.as_slice(), false)),
        );
        e.push(("model.png".into(), &self.icon, false));
        let mut res: Vec<_> = self
            .resources
            .iter()
            .map(|(n, b)| (format!("resources/{n}"), b.as_slice(), false))
            .collect();
        res.sort_by(|a, b| a.0.cmp(&b.0));
        e.extend(res);
        e
    }

    /// The `.fmu` archive as bytes.
    pub fn to_zip(&self) -> Result<Vec<u8>, String> {
        let mut zip = ZipWriter::new(std::io::Cursor::new(Vec::new()));
        let base = SimpleFileOptions::default()
            .compression_method(CompressionMethod::Deflated)
            .last_modified_time(DateTime::default());
        for (path, bytes, exe) in self.entries() {
            let opts = base.unix_permissions(if exe { 0o755 } else { 0o644 });
            zip.start_file(path.as_str(), opts)
                .map_err(|e| format!("{path}: {e}"))?;
            zip.write_all(bytes).map_err(|e| format!("{path}: {e}"))?;
        }
        Ok(zip.finish().map_err(|e| e.to_string())?.into_inner())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> FmuContents {
        FmuContents {
            identifier: "X".into(),
            model_description: "<fmiModelDescription/>".into(),
            binary: vec![1, 2, 3],
            documentation: vec![("index.html".into(), b"<html/>".to_vec())],
            icon: vec![0x89, b'P'],
            resources: vec![("scene.toml".into(), b"a = 1".to_vec())],
        }
    }

    #[test]
    fn layout_and_reproducibility() {
        let a = sample().to_zip().unwrap();
        assert_eq!(a, sample().to_zip().unwrap(), "same inputs, same bytes");
        let mut z = zip::ZipArchive::new(std::io::Cursor::new(a)).unwrap();
        let names: Vec<String> = (0..z.len())
            .map(|i| z.by_index(i).unwrap().name().unwrap().to_string())
            .collect();
        assert_eq!(
            names,
            [
                "modelDescription.xml",
                "binaries/linux64/X.so",
                "documentation/index.html",
                "model.png",
                "resources/scene.toml"
            ]
        );
        assert_eq!(
            z.by_name("binaries/linux64/X.so")
                .unwrap()
                .unix_mode()
                .unwrap()
                & 0o777,
            0o755
        );
    }
}
