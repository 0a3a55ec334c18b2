//! Files in and out, for every reader and writer of the workspace: input files read whole
//! (files and pipes, never a device) and output folders created with a message that says what
//! is in the way.

use std::path::Path;
#[cfg(not(unix))]
use std::path::PathBuf;

/// Characters of a sample's name kept in the names of files made for it (`synth --pabopto`,
/// `report`, `export`), so that those names stay within every file system's limit (255 bytes)
/// with the rest of the name.
pub const MAX_SAMPLE_CHARS: usize = 100;

/// The bytes of the input file at `path`, read whole: a regular file or a pipe (`<(...)`,
/// `/dev/stdin`). On Unix a device or a socket is refused with an
/// [`std::io::ErrorKind::InvalidInput`] error before anything is read: `/dev/zero` or
/// `/dev/full` never ends, and reading one had exhausted memory.
pub fn read_input(path: &Path) -> std::io::Result<Vec<u8>> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let kind = std::fs::metadata(path)?.file_type();
        if kind.is_char_device() || kind.is_block_device() || kind.is_socket() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "not a file or a pipe (a device or a socket)",
            ));
        }
    }
    std::fs::read(path)
}

/// The text of the input file at `path` ([`read_input`]), which must be UTF-8.
pub fn read_input_text(path: &Path) -> std::io::Result<String> {
    String::from_utf8(read_input(path)?)
        .map_err(|_| std::io::Error::new(std::io::ErrorKind::InvalidData, "not UTF-8 text"))
}

/// Creates the output folder `dir` and its parents if missing. A path, or the nearest of its
/// ancestors that exists, that is not a folder (a file, a device) is an
/// [`std::io::ErrorKind::AlreadyExists`] error that names it, where `create_dir_all` says only
/// "File exists" or "Not a directory".
pub fn create_folder(dir: &Path) -> std::io::Result<()> {
    // Without a trailing separator, which makes a file's path not exist at all.
    let bare = dir.components().as_path();
    if let Some(existing) = bare.ancestors().find(|a| a.exists())
        && !existing.is_dir()
    {
        let what = if existing == bare {
            "exists and is not a folder".to_owned()
        } else {
            format!("{} exists and is not a folder", existing.display())
        };
        return Err(std::io::Error::new(std::io::ErrorKind::AlreadyExists, what));
    }
    std::fs::create_dir_all(dir)
}

/// What identifies a file whatever path names it: on Unix its device and inode, so that a
/// hard link, a symbolic link, another spelling of the path and `/dev/stdin` named twice (one
/// pipe) are the same file; elsewhere its canonical path.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum FileId {
    #[cfg(unix)]
    Inode { device: u64, inode: u64 },
    #[cfg(not(unix))]
    Path(PathBuf),
}

impl FileId {
    /// The identity of the file at `path`, following symbolic links; `None` for a path that
    /// names nothing (reading it reports that).
    pub fn of(path: &Path) -> Option<Self> {
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt;
            let meta = std::fs::metadata(path).ok()?;
            Some(Self::Inode {
                device: meta.dev(),
                inode: meta.ino(),
            })
        }
        #[cfg(not(unix))]
        {
            path.canonicalize().ok().map(Self::Path)
        }
    }
}

/// Whether `a` and `b` name the same existing file ([`FileId`]).
pub fn same_file(a: &Path, b: &Path) -> bool {
    matches!((FileId::of(a), FileId::of(b)), (Some(a), Some(b)) if a == b)
}
