//! A library's error kept as the cause of a [`GeometryError`](super::GeometryError),
//! which is `Clone` and `PartialEq` where `std::io::Error`, `usvg::Error` and
//! `dxf::DxfError` are neither.

use std::fmt;
use std::sync::Arc;

/// Error `E`, shared by clones. Two are equal when they say the same words
/// (`E` has no `PartialEq` of its own).
#[derive(Debug)]
pub struct Cause<E>(Arc<E>);

impl<E> Cause<E> {
    /// Keeps `e`.
    pub(crate) fn new(e: E) -> Self {
        Cause(Arc::new(e))
    }

    /// The error itself.
    pub(crate) fn get(&self) -> &E {
        &self.0
    }
}

impl<E> Clone for Cause<E> {
    fn clone(&self) -> Self {
        Cause(Arc::clone(&self.0))
    }
}

impl<E: fmt::Display> PartialEq for Cause<E> {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0) || self.0.to_string() == other.0.to_string()
    }
}

impl<E: fmt::Display> fmt::Display for Cause<E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}

impl<E: std::error::Error + 'static> std::error::Error for Cause<E> {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(self.get())
    }
}

#[cfg(test)]
mod tests {
    use super::Cause;
    use std::error::Error;
    use std::io;

    #[test]
    fn it_says_its_error_and_gives_it_as_the_source() {
        let e = Cause::new(io::Error::new(io::ErrorKind::NotFound, "gone"));
        assert_eq!(e.to_string(), "gone");
        let io = e.source().and_then(|s| s.downcast_ref::<io::Error>());
        assert_eq!(io.map(io::Error::kind), Some(io::ErrorKind::NotFound));
        assert_eq!(e.clone(), e);
        assert_ne!(e, Cause::new(io::Error::other("other")));
    }
}
