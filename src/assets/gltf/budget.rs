//! The limits that keep a hostile file from hanging umbra or eating the machine: only regular
//! files are opened, and what is read and what is built from it each draw on a budget.

use std::cell::Cell;
use std::io::Read;
use std::path::Path;

/// Most bytes read for one model: the file itself and every buffer and image it names, from
/// files or data URIs, together.
pub const MAX_INPUT_BYTES: u64 = 1 << 30;

/// Most bytes built from one model: vertices, indices, animation keys, decoded textures with
/// their mipmaps, and the nodes and parts of its tree.
pub const MAX_DECODED_BYTES: u64 = 1 << 30;

/// Most objects (nodes, meshes, primitives, accessors, materials, ...) one file may hold. Each
/// costs a few hundred bytes once parsed while it may take two bytes of JSON, so they are
/// counted before the file is parsed.
pub const MAX_OBJECTS: usize = 1 << 18;

/// Most mesh parts one model may draw (a node instancing a mesh draws each of its primitives).
pub const MAX_PARTS: usize = 1 << 17;

/// Bytes left of one budget.
pub(super) struct Budget {
    what: &'static str,
    limit: u64,
    left: Cell<u64>,
}

impl Budget {
    /// The budget of bytes read.
    pub(super) fn input() -> Self {
        Budget { what: "its files hold", limit: MAX_INPUT_BYTES, left: Cell::new(MAX_INPUT_BYTES) }
    }

    /// The budget of bytes built.
    pub(super) fn decoded() -> Self {
        Budget {
            what: "it decodes to (vertices, keys, textures and nodes)",
            limit: MAX_DECODED_BYTES,
            left: Cell::new(MAX_DECODED_BYTES),
        }
    }

    /// Takes `n` bytes from the budget, or says the model is too large.
    pub(super) fn spend(&self, n: u64) -> Result<(), String> {
        match self.left.get().checked_sub(n) {
            Some(left) => {
                self.left.set(left);
                Ok(())
            }
            None => Err(format!("the model is too large: {} more than {}", self.what, bytes(self.limit))),
        }
    }

    /// Bytes still left.
    pub(super) fn left(&self) -> u64 {
        self.left.get()
    }
}

/// `n` bytes in the largest binary unit that keeps it at 1 or more ("1 GiB", "3.0 GiB").
pub(super) fn bytes(n: u64) -> String {
    const UNITS: [&str; 4] = ["bytes", "KiB", "MiB", "GiB"];
    let mut value = n as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit < UNITS.len() - 1 {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 || value.fract() == 0.0 {
        format!("{value} {}", UNITS[unit])
    } else {
        format!("{value:.1} {}", UNITS[unit])
    }
}

/// What kind of thing `path` is, when it is not a regular file (read through symbolic links).
fn not_a_file(meta: &std::fs::Metadata) -> Option<&'static str> {
    let kind = meta.file_type();
    if kind.is_file() {
        return None;
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return Some("a named pipe (FIFO)");
        }
        if kind.is_char_device() || kind.is_block_device() {
            return Some("a device");
        }
        if kind.is_socket() {
            return Some("a socket");
        }
    }
    Some(if kind.is_dir() { "a directory" } else { "not a regular file" })
}

/// The bytes of the regular file at `path` (called `shown` in messages), paid from `budget`:
/// anything else (a pipe that nobody writes, a device that never ends, a directory) is refused
/// before a byte is read, and a file larger than what is left of the budget is refused by its
/// size before it is read.
pub(super) fn read_file(path: &Path, shown: &str, budget: &Budget) -> Result<Vec<u8>, String> {
    let fail = |e: std::io::Error| format!("cannot read {shown}: {e}");
    let meta = std::fs::metadata(path).map_err(fail)?;
    if let Some(kind) = not_a_file(&meta) {
        return Err(format!("{shown} is {kind}, not a file; umbra reads models only from regular files"));
    }
    if meta.len() > budget.left() {
        return Err(format!(
            "{shown} is {}, more than the {} umbra reads for a model and the files it names",
            bytes(meta.len()),
            bytes(budget.limit)
        ));
    }
    budget.spend(meta.len())?;
    let mut data = Vec::with_capacity(meta.len() as usize);
    // A file that grows while it is read (or lies about its size, as /proc files do) stops at
    // what the budget still allows.
    let cap = meta.len().saturating_add(budget.left());
    std::fs::File::open(path).and_then(|f| f.take(cap.saturating_add(1)).read_to_end(&mut data)).map_err(fail)?;
    budget.spend((data.len() as u64).saturating_sub(meta.len()))?;
    Ok(data)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budgets_run_out_instead_of_memory() {
        let b = Budget::decoded();
        b.spend(MAX_DECODED_BYTES - 10).unwrap();
        b.spend(10).unwrap();
        let err = b.spend(1).unwrap_err();
        assert!(err.contains("too large") && err.contains("1 GiB"), "{err}");
    }

    #[test]
    fn sizes_read_plainly() {
        assert_eq!(bytes(12), "12 bytes");
        assert_eq!(bytes(1 << 30), "1 GiB");
        assert_eq!(bytes(3 << 30), "3 GiB");
        assert_eq!(bytes(1536), "1.5 KiB");
    }

    #[cfg(unix)]
    #[test]
    fn devices_and_directories_are_refused_before_reading() {
        let b = Budget::input();
        let err = read_file(Path::new("/dev/zero"), "zero", &b).unwrap_err();
        assert!(err.contains("zero is a device"), "{err}");
        let err = read_file(Path::new("."), "here", &b).unwrap_err();
        assert!(err.contains("is a directory"), "{err}");
        assert_eq!(b.left(), MAX_INPUT_BYTES, "nothing was read");
    }
}
