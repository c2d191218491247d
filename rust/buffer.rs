//! Output buffers whose allocation can fail with an error instead of aborting the process.

use std::alloc::{alloc_zeroed, Layout};

use crate::error::{Error, Result};

/// The error of an allocation of `what` (a noun phrase: "the frames") that cannot be had.
fn out_of_memory(what: &'static str, needed: String, hint: &'static str) -> Error {
    Error::TooLarge {
        what: format!("holding {what}").into(),
        needed,
        limit: "the memory this process can allocate".into(),
        hint,
    }
}

/// A zero-filled `Vec<f64>` of `len` elements, or [`Error::TooLarge`] if it cannot be had.
///
/// Zeroed memory from the allocator costs nothing up front for large sizes (fresh pages are
/// zero), unlike `try_reserve` followed by `resize`, which writes every element.
pub fn zeroed(len: usize, what: &'static str) -> Result<Vec<f64>> {
    zeroed_for(len, what, "ask for fewer frames or points")
}

/// As [`zeroed`], with `hint` saying what to ask for instead if it cannot be had.
pub fn zeroed_for(len: usize, what: &'static str, hint: &'static str) -> Result<Vec<f64>> {
    if len == 0 {
        return Ok(Vec::new());
    }
    let too_large = || {
        out_of_memory(
            what,
            format!("{len} float64 values ({:.3e} bytes)", len as f64 * 8.0),
            hint,
        )
    };
    let layout = Layout::array::<f64>(len).map_err(|_| too_large())?;
    // SAFETY: the layout has non-zero size; a null return is handled; the memory is
    // zero-initialised, which is a valid f64 (0.0), and `Vec` frees it with the same layout.
    unsafe {
        let ptr = alloc_zeroed(layout) as *mut f64;
        if ptr.is_null() {
            return Err(too_large());
        }
        Ok(Vec::from_raw_parts(ptr, len, len))
    }
}

/// An empty `Vec` with room for `len` items, or [`Error::TooLarge`] saying how much was asked
/// if it cannot be had (under an address-space limit, say), instead of aborting the process.
pub fn try_with_capacity<T>(len: usize, what: &'static str, hint: &'static str) -> Result<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(len).map_err(|_| {
        let bytes = len as f64 * std::mem::size_of::<T>() as f64;
        out_of_memory(what, format!("{len} values ({bytes:.3e} bytes)"), hint)
    })?;
    Ok(v)
}

/// The items of `iter` (of exactly `len` items) in a `Vec` allocated fallibly, see
/// [`try_with_capacity`].
pub fn try_collect<T>(
    iter: impl IntoIterator<Item = T>,
    len: usize,
    what: &'static str,
    hint: &'static str,
) -> Result<Vec<T>> {
    let mut v = try_with_capacity(len, what, hint)?;
    v.extend(iter.into_iter().take(len));
    Ok(v)
}

/// As [`try_collect`] for fallible items: the first error, or every item.
pub fn try_collect_results<T>(
    iter: impl IntoIterator<Item = Result<T>>,
    len: usize,
    what: &'static str,
    hint: &'static str,
) -> Result<Vec<T>> {
    let mut v = try_with_capacity(len, what, hint)?;
    for item in iter.into_iter().take(len) {
        v.push(item?);
    }
    Ok(v)
}

/// Checks, before a computation whose many small allocations add up to about `bytes`, that
/// the process can have that much now: a failed reservation is [`Error::TooLarge`] saying
/// how much was asked, where the allocations themselves would abort the process. The
/// reservation is released at once (it never touches its pages).
pub fn ensure_room(bytes: f64, what: &'static str, hint: &'static str) -> Result<()> {
    let too_large = || out_of_memory(what, format!("about {bytes:.3e} bytes"), hint);
    if bytes.is_nan() || bytes >= isize::MAX as f64 {
        return Err(too_large());
    }
    let mut probe: Vec<u8> = Vec::new();
    probe
        .try_reserve_exact(bytes as usize)
        .map_err(|_| too_large())
}
