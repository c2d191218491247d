//! Output buffers whose allocation can fail with an error instead of aborting the process.

use std::alloc::{alloc_zeroed, Layout};

use crate::error::{Error, Result};

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
    let too_large = || Error::TooLarge {
        what,
        needed: format!("{len} float64 values ({:.3e} bytes)", len as f64 * 8.0),
        limit: "the memory this process can allocate".into(),
        hint,
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
