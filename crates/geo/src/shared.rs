//! Copy-on-write storage for a geometry's large arrays: shared between clones until one of them writes, with the array's content hash cached beside it.
//!
//! A node that takes its input and changes P clones the input's geometry:
//! every other column (and the connectivity) stays shared, so the clone
//! copies nothing but P, and the output's content hash rehashes only P (the
//! shared columns carry the digests their first hashing cached).

use std::fmt;
use std::ops::Deref;
use std::sync::{Arc, OnceLock};

/// An array shared by reference count; [`Shared::make_mut`] copies it
/// first when another geometry holds it too.
pub struct Shared<T> {
    inner: Arc<Inner<T>>,
}

struct Inner<T> {
    data: T,
    /// The content hash of `data` (see `hash.rs`), once asked for.
    hash: OnceLock<u128>,
}

impl<T: Clone> Clone for Inner<T> {
    /// A copy about to be written: its hash is not the original's.
    fn clone(&self) -> Self {
        Inner {
            data: self.data.clone(),
            hash: OnceLock::new(),
        }
    }
}

impl<T> Shared<T> {
    pub fn new(data: T) -> Shared<T> {
        Shared {
            inner: Arc::new(Inner {
                data,
                hash: OnceLock::new(),
            }),
        }
    }

    /// Whether no other geometry holds this array (a write copies nothing).
    pub fn is_unique(&self) -> bool {
        Arc::strong_count(&self.inner) == 1
    }

    /// The cached content hash, computed by `f` on first use.
    pub fn hash_with(&self, f: impl FnOnce(&T) -> u128) -> u128 {
        *self.inner.hash.get_or_init(|| f(&self.inner.data))
    }

    /// Whether two arrays are one and the same (not merely equal).
    pub fn ptr_eq(a: &Shared<T>, b: &Shared<T>) -> bool {
        Arc::ptr_eq(&a.inner, &b.inner)
    }
}

impl<T: Clone> Shared<T> {
    /// The array to write: copied first if shared, its cached hash dropped.
    pub fn make_mut(&mut self) -> &mut T {
        let inner = Arc::make_mut(&mut self.inner);
        inner.hash = OnceLock::new();
        &mut inner.data
    }
}

impl<T> Clone for Shared<T> {
    /// Another holder of the same array: nothing is copied.
    fn clone(&self) -> Self {
        Shared {
            inner: Arc::clone(&self.inner),
        }
    }
}

impl<T> Deref for Shared<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.inner.data
    }
}

impl<T> From<T> for Shared<T> {
    fn from(data: T) -> Self {
        Shared::new(data)
    }
}

impl<A> FromIterator<A> for Shared<Vec<A>> {
    fn from_iter<I: IntoIterator<Item = A>>(iter: I) -> Self {
        Shared::new(iter.into_iter().collect())
    }
}

impl<'a, A> IntoIterator for &'a Shared<Vec<A>> {
    type Item = &'a A;
    type IntoIter = std::slice::Iter<'a, A>;
    fn into_iter(self) -> Self::IntoIter {
        self.inner.data.iter()
    }
}

impl<T: Default> Default for Shared<T> {
    fn default() -> Self {
        Shared::new(T::default())
    }
}

impl<T: PartialEq> PartialEq for Shared<T> {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.inner, &other.inner) || self.inner.data == other.inner.data
    }
}

impl<T: fmt::Debug> fmt::Debug for Shared<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.inner.data.fmt(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_clone_shares_until_written_and_a_write_forgets_the_hash() {
        let mut a = Shared::new(vec![1u32, 2, 3]);
        assert_eq!(a.hash_with(|v| v.len() as u128), 3);
        let b = a.clone();
        assert!(Shared::ptr_eq(&a, &b) && !a.is_unique());
        // The clone carries the digest: `f` is not called again.
        assert_eq!(b.hash_with(|_| unreachable!("cached")), 3);
        a.make_mut().push(4);
        assert!(!Shared::ptr_eq(&a, &b) && a.is_unique() && b.is_unique());
        assert_eq!(*b, vec![1, 2, 3]);
        assert_eq!(a.hash_with(|v| v.len() as u128), 4);
        // Written in place when unshared: the stale digest goes too.
        a.make_mut()[0] = 9;
        assert_eq!(a.hash_with(|v| v[0] as u128), 9);
        assert_eq!(*a, vec![9, 2, 3, 4]);
    }
}
