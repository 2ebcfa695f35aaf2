//! The packager: writes an `.fmu` (a zip archive) with the layout of FMI 2.0, section 2.3, with a
//! binary for every platform built ([`Platform`]).
//!
//! Entries are written in a fixed order with a fixed time stamp and fixed permissions, so the
//! same inputs give a byte-identical archive.

use std::io::Write;
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, DateTime, ZipWriter};

/// A platform an FMU carries a binary for: `binaries/<folder>/<modelIdentifier>.<extension>`.
///
/// The folder names are those FMI hosts look in. FMI 2.0 standardizes `win64`, `linux64` and
/// `darwin64` (one universal binary serves Intel and Apple-silicon Macs: FMPy 0.3.32 and the
/// Reference FMUs' `fmusim` look in `darwin64` on both); since FMI 2.0.4 (section 2.3) any other
/// platform takes FMI 3.0's platform tuple, so the aarch64 Linux library is in `aarch64-linux`
/// (`linux64` holds the x86-64 one).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Platform {
    Linux64,
    Aarch64Linux,
    Win64,
    Darwin64,
}

impl Platform {
    /// Every platform, in the order of the archive's entries.
    pub const ALL: [Platform; 4] = [
        Platform::Linux64,
        Platform::Aarch64Linux,
        Platform::Win64,
        Platform::Darwin64,
    ];

    /// The folder under `binaries/`.
    pub fn folder(self) -> &'static str {
        match self {
            Platform::Linux64 => "linux64",
            Platform::Aarch64Linux => "aarch64-linux",
            Platform::Win64 => "win64",
            Platform::Darwin64 => "darwin64",
        }
    }

    /// The shared library's file extension.
    pub fn extension(self) -> &'static str {
        match self {
            Platform::Linux64 | Platform::Aarch64Linux => "so",
            Platform::Win64 => "dll",
            Platform::Darwin64 => "dylib",
        }
    }

    /// The binary's path inside the archive.
    pub fn path(self, identifier: &str) -> String {
        format!(
            "binaries/{}/{identifier}.{}",
            self.folder(),
            self.extension()
        )
    }

    /// The folders under `binaries/` of an FMI 3.0 FMU: FMI 3.0's platform tuples (section
    /// 2.5.1). The one universal macOS binary serves both of macOS's tuples.
    pub fn folders3(self) -> &'static [&'static str] {
        match self {
            Platform::Linux64 => &["x86_64-linux"],
            Platform::Aarch64Linux => &["aarch64-linux"],
            Platform::Win64 => &["x86_64-windows"],
            Platform::Darwin64 => &["x86_64-darwin", "aarch64-darwin"],
        }
    }

    /// The binary's folders in an FMU of this FMI version.
    pub fn folders(self, version: Fmi) -> Vec<&'static str> {
        match version {
            Fmi::V2 => vec![self.folder()],
            Fmi::V3 => self.folders3().to_vec(),
        }
    }

    /// What the binary runs on, for the documentation.
    pub fn runs_on(self) -> &'static str {
        match self {
            Platform::Linux64 => {
                "Linux on x86-64 with glibc 2.17 or later (RHEL/CentOS 7 and later)"
            }
            Platform::Aarch64Linux => {
                "Linux on 64-bit ARM (aarch64) with glibc 2.17 or later; FMI 2.0 hosts that look \
                 in binaries/linux64 on ARM need this folder's library instead"
            }
            Platform::Win64 => "Windows 10 and later on x86-64",
            Platform::Darwin64 => {
                "macOS 10.12 and later on Intel, macOS 11 and later on Apple silicon (one \
                 universal binary)"
            }
        }
    }
}

/// The FMI version of an FMU: the shape of its description and its platform folders.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Fmi {
    #[default]
    V2,
    V3,
}

/// The `documentation/index.html` placeholder that [`FmuContents::to_zip`] replaces with the
/// platforms of the binaries it packs (written by `docs::html::page_html`).
pub const PLATFORMS_MARK: &str = "<!-- platforms -->";

/// The `documentation/index.html` placeholder for the FMI version of the FMU that carries the
/// page ([`version_html`]): the same page serves both.
pub const VERSION_MARK: &str = "<!-- fmi version -->";

/// What the page says of the FMI version of the FMU it is in (`None`: read outside an FMU).
pub fn version_html(version: Option<Fmi>) -> &'static str {
    match version {
        Some(Fmi::V2) => "FMI 2.0",
        Some(Fmi::V3) => {
            "FMI 3.0 (the text below names FMI 2.0's calls; FMI 3.0's counterparts are \
             <code>fmi3DoStep</code>, <code>fmi3SetFloat64</code>, \
             <code>fmi3CompletedIntegratorStep</code>, ...; input derivatives are FMI 2.0's only)"
        }
        None => "FMI 2.0 and FMI 3.0",
    }
}

/// The documentation's section on the platforms of `binaries` (in an FMU of FMI 2.0).
pub fn platforms_html(platforms: &[Platform]) -> String {
    platforms_html_of(platforms, Fmi::V2)
}

/// The documentation's section on the platforms of `binaries` in an FMU of `version`.
pub fn platforms_html_of(platforms: &[Platform], version: Fmi) -> String {
    let mut out = String::from("<h2>Platforms</h2>\n<p>Binaries in this FMU:</p>\n<ul>\n");
    for p in platforms {
        let folders: Vec<String> = (p.folders(version).iter())
            .map(|f| format!("<code>binaries/{f}</code>"))
            .collect();
        out.push_str(&format!(
            "<li>{}: {}</li>\n",
            folders.join(" and "),
            p.runs_on()
        ));
    }
    out.push_str("</ul>");
    out
}

/// The platforms section of a page read outside an FMU (`bindery docs`): every platform `build`
/// makes a binary for when its toolchain is present.
pub fn platforms_all_html() -> String {
    platforms_html(&Platform::ALL).replace(
        "<p>Binaries in this FMU:</p>",
        "<p>A built FMU carries a binary for each of these platforms whose toolchain was present \
         at build; the copy of this page inside the FMU lists those it has:</p>",
    )
}

/// A shared library per platform.
pub type Binaries = Vec<(Platform, Vec<u8>)>;

/// Everything that goes into one FMU.
#[derive(Clone, Debug, Default)]
pub struct FmuContents {
    /// `modelIdentifier`: names the binaries `binaries/<platform>/<id>.<so|dll|dylib>`.
    pub identifier: String,
    pub model_description: String,
    /// The shared library built for each platform (at least one).
    pub binaries: Binaries,
    /// Files of `documentation/` (index.html first, then figures), by file name.
    pub documentation: Vec<(String, Vec<u8>)>,
    /// The `model.png` icon.
    pub icon: Vec<u8>,
    /// Files of `resources/`, by relative path.
    pub resources: Vec<(String, Vec<u8>)>,
    /// The FMI version (`model_description`'s): where the binaries go, and the icon (FMI 2.0:
    /// `model.png`; FMI 3.0: `terminalsAndIcons/icon.png`).
    pub fmi: Fmi,
    /// FMI 3.0: `terminalsAndIcons/terminalsAndIcons.xml`.
    pub terminals: Option<String>,
    /// Files of `extra/` (layered standards), by relative path.
    pub extra: Vec<(String, Vec<u8>)>,
}

impl FmuContents {
    /// The archive's entries: (path, bytes, executable). `documentation/index.html` states the
    /// platforms of the binaries, in place of [`PLATFORMS_MARK`].
    fn entries(&self) -> Vec<(String, std::borrow::Cow<'_, [u8]>, bool)> {
        use std::borrow::Cow;
        let mut binaries: Vec<&(Platform, Vec<u8>)> = self.binaries.iter().collect();
        binaries.sort_by_key(|(p, _)| *p);
        let platforms: Vec<Platform> = binaries.iter().map(|(p, _)| *p).collect();
        let mut e: Vec<(String, Cow<'_, [u8]>, bool)> = vec![(
            "modelDescription.xml".into(),
            Cow::Borrowed(self.model_description.as_bytes()),
            false,
        )];
        for (p, b) in &binaries {
            for folder in p.folders(self.fmi) {
                let path = format!("binaries/{folder}/{}.{}", self.identifier, p.extension());
                e.push((path, Cow::Borrowed(b.as_slice()), true));
            }
        }
        e.extend(self.documentation.iter().map(|(n, b)| {
            let bytes = match std::str::from_utf8(b) {
                Ok(page) if n == "index.html" && page.contains(PLATFORMS_MARK) => Cow::Owned(
                    page.replace(PLATFORMS_MARK, &platforms_html_of(&platforms, self.fmi))
                        .replace(VERSION_MARK, version_html(Some(self.fmi)))
                        .into_bytes(),
                ),
                _ => Cow::Borrowed(b.as_slice()),
            };
            (format!("documentation/{n}"), bytes, false)
        }));
        match self.fmi {
            Fmi::V2 => e.push(("model.png".into(), Cow::Borrowed(&self.icon), false)),
            Fmi::V3 => {
                e.push((
                    "terminalsAndIcons/icon.png".into(),
                    Cow::Borrowed(&self.icon),
                    false,
                ));
                if let Some(t) = &self.terminals {
                    e.push((
                        "terminalsAndIcons/terminalsAndIcons.xml".into(),
                        Cow::Borrowed(t.as_bytes()),
                        false,
                    ));
                }
            }
        }
        let mut extra: Vec<_> = (self.extra.iter())
            .map(|(n, b)| (format!("extra/{n}"), Cow::Borrowed(b.as_slice()), false))
            .collect();
        extra.sort_by(|a, b| a.0.cmp(&b.0));
        e.extend(extra);
        let mut res: Vec<_> = self
            .resources
            .iter()
            .map(|(n, b)| (format!("resources/{n}"), Cow::Borrowed(b.as_slice()), false))
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
            .compression_level(Some(9))
            .last_modified_time(DateTime::default());
        if self.binaries.is_empty() {
            return Err(format!("{}: no binary for any platform", self.identifier));
        }
        for (path, bytes, exe) in self.entries() {
            let opts = base.unix_permissions(if exe { 0o755 } else { 0o644 });
            zip.start_file(path.as_str(), opts)
                .map_err(|e| format!("{path}: {e}"))?;
            zip.write_all(&bytes).map_err(|e| format!("{path}: {e}"))?;
        }
        Ok(zip.finish().map_err(|e| e.to_string())?.into_inner())
    }
}

/// The binaries of `identifier` in an `.fmu` archive (`fmu`): one per platform folder present,
/// in [`Platform::ALL`]'s order; an archive with none is an error.
pub fn binaries_in(fmu: &[u8], identifier: &str) -> Result<Binaries, String> {
    let mut zip = zip::ZipArchive::new(std::io::Cursor::new(fmu)).map_err(|e| e.to_string())?;
    let mut out = Binaries::new();
    for p in Platform::ALL {
        let path = p.path(identifier);
        let Ok(mut f) = zip.by_name(&path) else {
            continue;
        };
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(&mut f, &mut bytes).map_err(|e| format!("{path}: {e}"))?;
        out.push((p, bytes));
    }
    if out.is_empty() {
        return Err(format!(
            "no binaries/<platform>/{identifier}.* in the archive"
        ));
    }
    Ok(out)
}

/// One universal ("fat") Mach-O binary of thin 64-bit Mach-O `slices` (e.g. x86-64 and arm64), as
/// Apple's `lipo -create` lays it out: a big-endian header with, per slice, its CPU type and
/// subtype (read from the slice's own header), offset, size and alignment, and each slice at an
/// offset aligned to 2^14 bytes (arm64's 16 KiB pages). The slices are copied unchanged, so an
/// arm64 slice keeps its code signature.
pub fn universal_macho(slices: &[&[u8]]) -> Result<Vec<u8>, String> {
    const FAT_MAGIC: u32 = 0xcafe_babe;
    const MH_MAGIC_64: u32 = 0xfeed_facf;
    const ALIGN_LOG2: u32 = 14;
    let align = 1usize << ALIGN_LOG2;
    let word = |b: &[u8], at: usize| u32::from_le_bytes(b[at..at + 4].try_into().unwrap());
    let mut header = Vec::new();
    header.extend_from_slice(&FAT_MAGIC.to_be_bytes());
    header.extend_from_slice(&(slices.len() as u32).to_be_bytes());
    let mut offset = align;
    let mut body = Vec::new();
    for (i, s) in slices.iter().enumerate() {
        if s.len() < 12 || word(s, 0) != MH_MAGIC_64 {
            return Err(format!(
                "slice {i} is not a 64-bit little-endian Mach-O binary"
            ));
        }
        let (cputype, cpusubtype) = (word(s, 4), word(s, 8));
        if slices[..i].iter().any(|o| word(o, 4) == cputype) {
            return Err(format!("two slices for CPU type {cputype:#x}"));
        }
        for x in [
            cputype,
            cpusubtype,
            offset as u32,
            s.len() as u32,
            ALIGN_LOG2,
        ] {
            header.extend_from_slice(&x.to_be_bytes());
        }
        body.resize(offset - align, 0);
        body.extend_from_slice(s);
        offset = (align + body.len()).next_multiple_of(align);
    }
    header.resize(align, 0);
    header.extend_from_slice(&body);
    Ok(header)
}

/// The names of a zip archive's entries, in order (tests).
#[cfg(test)]
pub(crate) fn entry_names(zip: &[u8]) -> Vec<String> {
    let mut z = zip::ZipArchive::new(std::io::Cursor::new(zip)).unwrap();
    (0..z.len())
        .map(|i| z.by_index(i).unwrap().name().unwrap().to_string())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> FmuContents {
        FmuContents {
            identifier: "X".into(),
            model_description: "<fmiModelDescription/>".into(),
            binaries: vec![
                (Platform::Win64, vec![4, 5]),
                (Platform::Linux64, vec![1, 2, 3]),
            ],
            documentation: vec![(
                "index.html".into(),
                format!("<html>{VERSION_MARK} {PLATFORMS_MARK}</html>").into_bytes(),
            )],
            icon: vec![0x89, b'P'],
            resources: vec![("scene.toml".into(), b"a = 1".to_vec())],
            fmi: Fmi::V2,
            terminals: None,
            extra: vec![],
        }
    }

    #[test]
    fn an_fmi3_fmu_has_the_platform_tuples() {
        let fmu = FmuContents {
            fmi: Fmi::V3,
            binaries: vec![(Platform::Darwin64, vec![9]), (Platform::Linux64, vec![1])],
            terminals: Some("<fmiTerminalsAndIcons/>".into()),
            ..sample()
        };
        let zip = fmu.to_zip().unwrap();
        let names = entry_names(&zip);
        assert!(!names.iter().any(|n| n == "model.png"), "{names:?}");
        for p in [
            "terminalsAndIcons/icon.png",
            "terminalsAndIcons/terminalsAndIcons.xml",
            "binaries/x86_64-linux/X.so",
            "binaries/x86_64-darwin/X.dylib",
            "binaries/aarch64-darwin/X.dylib",
        ] {
            assert!(names.iter().any(|n| n == p), "{p} in {names:?}");
        }
        assert!(!names.iter().any(|n| n.contains("linux64")), "{names:?}");
        let mut z = zip::ZipArchive::new(std::io::Cursor::new(zip)).unwrap();
        let mut page = String::new();
        std::io::Read::read_to_string(
            &mut z.by_name("documentation/index.html").unwrap(),
            &mut page,
        )
        .unwrap();
        assert!(
            page.contains(
                "<code>binaries/x86_64-darwin</code> and <code>binaries/aarch64-darwin</code>"
            ),
            "{page}"
        );
        assert!(
            page.starts_with("<html>FMI 3.0 (") && !page.contains(VERSION_MARK),
            "{page}"
        );
    }

    #[test]
    fn binaries_are_read_back_from_an_archive_per_platform() {
        let zip = sample().to_zip().unwrap();
        let back = binaries_in(&zip, "X").unwrap();
        assert_eq!(
            back,
            vec![
                (Platform::Linux64, vec![1, 2, 3]),
                (Platform::Win64, vec![4, 5])
            ]
        );
        let err = binaries_in(&zip, "Y").unwrap_err();
        assert!(err.contains("binaries/<platform>/Y"), "{err}");
    }

    #[test]
    fn layout_and_reproducibility() {
        let a = sample().to_zip().unwrap();
        assert_eq!(a, sample().to_zip().unwrap(), "same inputs, same bytes");
        let names = entry_names(&a);
        let mut z = zip::ZipArchive::new(std::io::Cursor::new(a)).unwrap();
        assert_eq!(
            names,
            [
                "modelDescription.xml",
                "binaries/linux64/X.so",
                "binaries/win64/X.dll",
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
        let mut page = String::new();
        std::io::Read::read_to_string(
            &mut z.by_name("documentation/index.html").unwrap(),
            &mut page,
        )
        .unwrap();
        assert!(!page.contains(PLATFORMS_MARK), "{page}");
        assert!(page.starts_with("<html>FMI 2.0 <h2>"), "{page}");
        assert!(
            page.contains("<code>binaries/linux64</code>: Linux on x86-64"),
            "{page}"
        );
        assert!(
            page.contains("<code>binaries/win64</code>: Windows 10"),
            "{page}"
        );
        assert!(
            !page.contains("darwin64"),
            "only the platforms packed: {page}"
        );
    }

    #[test]
    fn no_binary_no_fmu() {
        let fmu = FmuContents {
            binaries: vec![],
            ..sample()
        };
        assert!(fmu.to_zip().unwrap_err().contains("no binary"));
    }

    /// A thin Mach-O header: magic, CPU type, subtype, then filler.
    fn thin(cputype: u32, subtype: u32, len: usize) -> Vec<u8> {
        let mut b = Vec::new();
        for w in [0xfeed_facf_u32, cputype, subtype] {
            b.extend_from_slice(&w.to_le_bytes());
        }
        b.resize(len, 0xab);
        b
    }

    #[test]
    fn universal_binary_layout() {
        let (x86, arm) = (thin(0x0100_0007, 3, 40_000), thin(0x0100_000c, 0, 20_000));
        let fat = universal_macho(&[&x86, &arm]).unwrap();
        let be = |at: usize| u32::from_be_bytes(fat[at..at + 4].try_into().unwrap());
        assert_eq!((be(0), be(4)), (0xcafe_babe, 2));
        // x86-64 at 16 KiB, arm64 at the next 16 KiB boundary after it: 16384 + 40000 -> 65536
        assert_eq!(
            [be(8), be(12), be(16), be(20), be(24)],
            [0x0100_0007, 3, 16384, 40_000, 14]
        );
        assert_eq!(
            [be(28), be(32), be(36), be(40), be(44)],
            [0x0100_000c, 0, 65536, 20_000, 14]
        );
        assert_eq!(&fat[16384..16384 + 40_000], x86.as_slice());
        assert_eq!(&fat[65536..], arm.as_slice());
        assert!(
            universal_macho(&[&x86, &x86]).is_err(),
            "one slice per CPU type"
        );
        assert!(universal_macho(&[b"\x7fELF........"]).is_err());
    }
}
