//! Reading accessors with every range checked: a broken offset, stride or count is an error
//! that says which accessor and by how much, never a panic or an out-of-bounds read.

use super::budget::Budget;
use gltf::accessor::{DataType, Dimensions};
use std::borrow::Cow;
use std::cell::RefCell;
use std::collections::HashMap;
use std::rc::Rc;

/// Most components an accessor without a buffer view (all zeros) may have.
const MAX_ZERO_COMPONENTS: usize = 1 << 24;

/// Reads all of one accessor's components from the buffers.
type Decoder<T> = fn(&gltf::Accessor<'_>, &[Cow<'_, [u8]>]) -> Result<Vec<T>, String>;

/// A file's buffers with each accessor decoded once, and the budget of what is built from them.
pub(super) struct Data<'a> {
    buffers: &'a [Cow<'a, [u8]>],
    floats: RefCell<HashMap<usize, Rc<Vec<f32>>>>,
    ints: RefCell<HashMap<usize, Rc<Vec<u32>>>>,
    /// Bytes left to build with (see [`super::MAX_DECODED_BYTES`]).
    pub budget: Budget,
    /// The file uses KHR_mesh_quantization: vertex attributes may be small integers.
    pub quantized: bool,
}

impl<'a> Data<'a> {
    pub(super) fn new(buffers: &'a [Cow<'a, [u8]>], quantized: bool) -> Self {
        Data { buffers, floats: RefCell::default(), ints: RefCell::default(), budget: Budget::decoded(), quantized }
    }

    /// Takes `n` bytes from the budget, or says the model is too large.
    pub(super) fn spend(&self, n: usize) -> Result<(), String> {
        self.budget.spend(n as u64)
    }

    /// The bytes of buffer view `view`, checked against its buffer.
    pub(super) fn view(&self, view: &gltf::buffer::View<'_>) -> Result<&'a [u8], String> {
        view_bytes(view, self.buffers)
    }

    /// The accessor's components as floats (see [`floats`]), decoded once.
    pub(super) fn floats(&self, acc: &gltf::Accessor<'_>) -> Result<Rc<Vec<f32>>, String> {
        self.cached(&self.floats, acc, floats)
    }

    /// The accessor's components as integers (see [`ints`]), decoded once.
    pub(super) fn ints(&self, acc: &gltf::Accessor<'_>) -> Result<Rc<Vec<u32>>, String> {
        self.cached(&self.ints, acc, ints)
    }

    /// `acc` decoded by `decode`, from `cache` or, the first time, paid from the budget.
    fn cached<T>(
        &self,
        cache: &RefCell<HashMap<usize, Rc<Vec<T>>>>,
        acc: &gltf::Accessor<'_>,
        decode: Decoder<T>,
    ) -> Result<Rc<Vec<T>>, String> {
        if let Some(v) = cache.borrow().get(&acc.index()) {
            return Ok(v.clone());
        }
        self.spend(acc.count().saturating_mul(components(acc)).saturating_mul(size_of::<T>()))?;
        let v = Rc::new(decode(acc, self.buffers)?);
        cache.borrow_mut().insert(acc.index(), v.clone());
        Ok(v)
    }
}

/// Which component types (and whether normalized) glTF allows for one use of an accessor.
pub(super) type Formats = &'static [(DataType, bool)];

/// Floats only.
pub(super) const FLOAT: Formats = &[(DataType::F32, false)];
/// Floats, or unsigned bytes and shorts normalized to 0..1.
pub(super) const FLOAT_OR_UNORM: Formats = &[(DataType::F32, false), (DataType::U8, true), (DataType::U16, true)];
/// Floats, or any byte or short normalized (rotation keys).
pub(super) const FLOAT_OR_NORM: Formats =
    &[(DataType::F32, false), (DataType::I8, true), (DataType::U8, true), (DataType::I16, true), (DataType::U16, true)];
/// Any byte or short, normalized or not, or floats (KHR_mesh_quantization's positions).
pub(super) const QUANTIZED: Formats = &[
    (DataType::F32, false),
    (DataType::I8, true),
    (DataType::I8, false),
    (DataType::U8, true),
    (DataType::U8, false),
    (DataType::I16, true),
    (DataType::I16, false),
    (DataType::U16, true),
    (DataType::U16, false),
];
/// Signed bytes and shorts normalized, or floats (KHR_mesh_quantization's normals).
pub(super) const FLOAT_OR_SNORM: Formats = &[(DataType::F32, false), (DataType::I8, true), (DataType::I16, true)];
/// Unsigned bytes and shorts, not normalized (joint indices).
pub(super) const UINT_SMALL: Formats = &[(DataType::U8, false), (DataType::U16, false)];
/// Unsigned bytes, shorts and ints, not normalized (vertex indices).
pub(super) const UINT: Formats = &[(DataType::U8, false), (DataType::U16, false), (DataType::U32, false)];

fn format_name(ty: DataType, normalized: bool) -> String {
    let name = match ty {
        DataType::I8 => "signed bytes",
        DataType::U8 => "unsigned bytes",
        DataType::I16 => "signed shorts",
        DataType::U16 => "unsigned shorts",
        DataType::U32 => "unsigned ints",
        DataType::F32 => "floats",
    };
    if normalized { format!("normalized {name}") } else { name.to_string() }
}

/// Refuses an accessor whose component type glTF does not allow for `what` (with `extension`
/// named when it is what would allow it).
pub(super) fn check_format(
    acc: &gltf::Accessor<'_>,
    allowed: Formats,
    what: &str,
    extension: Option<&str>,
) -> Result<(), String> {
    let found = (acc.data_type(), acc.normalized());
    if allowed.contains(&found) {
        return Ok(());
    }
    let names: Vec<String> = allowed.iter().map(|&(t, n)| format_name(t, n)).collect();
    let unless =
        extension.map_or(String::new(), |e| format!(" (more with the extension {e}, which the file does not use)"));
    Err(format!(
        "{what} (accessor {}) holds {}, but glTF allows only {} there{unless}",
        acc.index(),
        format_name(found.0, found.1),
        names.join(", ")
    ))
}

/// Refuses a vertex attribute whose elements do not start on 4-byte boundaries, as glTF asks.
pub(super) fn check_vertex_alignment(acc: &gltf::Accessor<'_>, what: &str) -> Result<(), String> {
    let Some(view) = acc.view() else { return Ok(()) };
    let (cols, _, column) = shape(acc.dimensions(), acc.data_type().size());
    let stride = view.stride().unwrap_or(cols * column);
    if !acc.offset().is_multiple_of(4) || !stride.is_multiple_of(4) {
        return Err(format!(
            "{what} (accessor {}): each element of a vertex attribute must start on a 4-byte boundary, \
             but its elements are {stride} bytes apart from byte {}",
            acc.index(),
            acc.offset()
        ));
    }
    Ok(())
}

/// Every component of every element as f32; normalized integers map to 0..1 or -1..1.
fn floats(acc: &gltf::Accessor<'_>, buffers: &[Cow<'_, [u8]>]) -> Result<Vec<f32>, String> {
    let (ty, normalized) = (acc.data_type(), acc.normalized());
    decode(acc, buffers, |b| to_f32(b, ty, normalized))
}

/// Every component of every element as an integer; floats are refused.
fn ints(acc: &gltf::Accessor<'_>, buffers: &[Cow<'_, [u8]>]) -> Result<Vec<u32>, String> {
    let ty = acc.data_type();
    if ty == DataType::F32 {
        return Err(format!("accessor {} holds floats where integers are needed", acc.index()));
    }
    decode(acc, buffers, |b| to_u32(b, ty))
}

/// Components per element of an accessor.
pub(super) fn components(acc: &gltf::Accessor<'_>) -> usize {
    acc.dimensions().multiplicity()
}

/// Columns, rows and bytes per column of one element (matrix columns are padded to 4 bytes).
fn shape(dims: Dimensions, size: usize) -> (usize, usize, usize) {
    let (cols, rows) = match dims {
        Dimensions::Mat2 => (2, 2),
        Dimensions::Mat3 => (3, 3),
        Dimensions::Mat4 => (4, 4),
        d => (1, d.multiplicity()),
    };
    let column = if cols > 1 { (rows * size).div_ceil(4) * 4 } else { rows * size };
    (cols, rows, column)
}

fn decode<T: Copy + Default>(
    acc: &gltf::Accessor<'_>,
    buffers: &[Cow<'_, [u8]>],
    f: impl Fn(&[u8]) -> T,
) -> Result<Vec<T>, String> {
    let i = acc.index();
    let size = acc.data_type().size();
    let (cols, rows, column) = shape(acc.dimensions(), size);
    let element = cols * column;
    let count = acc.count();
    let mut out = match acc.view() {
        Some(view) => {
            let data = view_bytes(&view, buffers)?;
            let stride = view.stride().unwrap_or(element);
            if stride < element {
                return Err(format!(
                    "accessor {i}: its view's stride of {stride} bytes is less than one element ({element})"
                ));
            }
            let needed = match count {
                0 => Some(0),
                n => stride
                    .checked_mul(n - 1)
                    .and_then(|s| s.checked_add(acc.offset()))
                    .and_then(|s| s.checked_add(element)),
            };
            match needed {
                Some(n) if n <= data.len() => {}
                _ => {
                    return Err(format!(
                        "accessor {i} is out of range: {count} elements from byte {} need more than the {} bytes of buffer view {}",
                        acc.offset(),
                        data.len(),
                        view.index()
                    ));
                }
            }
            let mut out = Vec::with_capacity(count * cols * rows);
            for e in 0..count {
                let base = acc.offset() + e * stride;
                for c in 0..cols {
                    for r in 0..rows {
                        let at = base + c * column + r * size;
                        out.push(f(&data[at..at + size]));
                    }
                }
            }
            out
        }
        None if count.saturating_mul(cols * rows) <= MAX_ZERO_COMPONENTS => vec![T::default(); count * cols * rows],
        None => return Err(format!("accessor {i} has {count} elements and no data")),
    };
    if let Some(sparse) = acc.sparse() {
        apply_sparse(&sparse, i, count, cols * rows, size, buffers, &f, &mut out)?;
    }
    Ok(out)
}

/// Replaces the elements a sparse accessor lists.
#[allow(clippy::too_many_arguments)]
fn apply_sparse<T>(
    sparse: &gltf::accessor::sparse::Sparse<'_>,
    i: usize,
    count: usize,
    comps: usize,
    size: usize,
    buffers: &[Cow<'_, [u8]>],
    f: &impl Fn(&[u8]) -> T,
    out: &mut [T],
) -> Result<(), String> {
    let n = sparse.count();
    let (indices, values) = (sparse.indices(), sparse.values());
    let index_size = match indices.index_type() {
        gltf::accessor::sparse::IndexType::U8 => 1,
        gltf::accessor::sparse::IndexType::U16 => 2,
        gltf::accessor::sparse::IndexType::U32 => 4,
    };
    let index_bytes = view_bytes(&indices.view(), buffers)?;
    let value_bytes = view_bytes(&values.view(), buffers)?;
    let fits = |data: &[u8], offset: usize, each: usize| {
        n.checked_mul(each).and_then(|b| b.checked_add(offset)).is_some_and(|end| end <= data.len())
    };
    if !fits(index_bytes, indices.offset(), index_size) || !fits(value_bytes, values.offset(), comps * size) {
        return Err(format!("accessor {i}: its sparse indices or values run past their buffer views"));
    }
    let mut last = None;
    for k in 0..n {
        let at = indices.offset() + k * index_size;
        let mut target = 0usize;
        for (b, byte) in index_bytes[at..at + index_size].iter().enumerate() {
            target |= (*byte as usize) << (8 * b);
        }
        if target >= count {
            return Err(format!("accessor {i}: sparse index {target} is past its {count} elements"));
        }
        // A repeated index would make the element depend on the order the values are read in.
        if let Some(before) = last.filter(|&before| before >= target) {
            return Err(format!(
                "accessor {i}: sparse index {target} comes after {before}; glTF asks for strictly increasing indices"
            ));
        }
        last = Some(target);
        for c in 0..comps {
            let at = values.offset() + (k * comps + c) * size;
            out[target * comps + c] = f(&value_bytes[at..at + size]);
        }
    }
    Ok(())
}

/// The bytes of a buffer view, checked against its buffer.
fn view_bytes<'a>(view: &gltf::buffer::View<'_>, buffers: &'a [Cow<'a, [u8]>]) -> Result<&'a [u8], String> {
    let buffer = &buffers[view.buffer().index()];
    let end = view.offset().checked_add(view.length());
    match end {
        Some(end) if end <= buffer.len() => Ok(&buffer[view.offset()..end]),
        _ => Err(format!(
            "buffer view {} ({} bytes from byte {}) runs past the end of buffer {} ({} bytes)",
            view.index(),
            view.length(),
            view.offset(),
            view.buffer().index(),
            buffer.len()
        )),
    }
}

fn to_f32(b: &[u8], ty: DataType, normalized: bool) -> f32 {
    let (v, scale) = match ty {
        DataType::I8 => (b[0] as i8 as f32, 127.0),
        DataType::U8 => (b[0] as f32, 255.0),
        DataType::I16 => (i16::from_le_bytes([b[0], b[1]]) as f32, 32767.0),
        DataType::U16 => (u16::from_le_bytes([b[0], b[1]]) as f32, 65535.0),
        DataType::U32 => (u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32, 1.0),
        DataType::F32 => return f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
    };
    if normalized { (v / scale).max(-1.0) } else { v }
}

fn to_u32(b: &[u8], ty: DataType) -> u32 {
    match ty {
        DataType::I8 | DataType::U8 => b[0] as u32,
        DataType::I16 | DataType::U16 => u16::from_le_bytes([b[0], b[1]]) as u32,
        _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalized_integers_map_to_unit_ranges() {
        assert_eq!(to_f32(&[255], DataType::U8, true), 1.0);
        assert_eq!(to_f32(&[0x80], DataType::I8, true), -1.0, "-128 clamps to -1");
        assert_eq!(to_f32(&[0xff, 0x7f], DataType::I16, true), 1.0);
        assert_eq!(to_f32(&[7, 0], DataType::U16, false), 7.0);
    }

    #[test]
    fn formats_are_named_when_refused() {
        assert_eq!(format_name(DataType::U8, true), "normalized unsigned bytes");
        assert!(QUANTIZED.contains(&(DataType::U8, false)) && !FLOAT_OR_UNORM.contains(&(DataType::U8, false)));
    }

    #[test]
    fn matrix_columns_are_padded_to_four_bytes() {
        assert_eq!(shape(Dimensions::Mat3, 1), (3, 3, 4));
        assert_eq!(shape(Dimensions::Mat2, 2), (2, 2, 4));
        assert_eq!(shape(Dimensions::Mat4, 4), (4, 4, 16));
        assert_eq!(shape(Dimensions::Vec3, 1), (1, 3, 3));
    }
}
