//! Memos: the values made for the last few keys, least recently used dropped first. They hold
//! what frames would otherwise remake: the tables and textures of an animation or the editor's
//! preview, and the pipelines and materials made on a GPU device.

use std::sync::{Arc, Mutex};

/// The values made for the last `N` keys used (the least recently used is dropped first).
pub(crate) struct Memo<K, T, const N: usize> {
    /// Least recently used first.
    entries: Mutex<Vec<(K, T)>>,
}

impl<K: PartialEq, T: Clone, const N: usize> Memo<K, T, N> {
    /// An empty memo.
    pub(crate) const fn new() -> Self {
        Memo {
            entries: Mutex::new(Vec::new()),
        }
    }

    /// The value for `key`, made (outside the lock) and kept if it is missing; a failure is
    /// returned and not kept.
    pub(crate) fn get_or_make<E>(
        &self,
        key: K,
        make: impl FnOnce() -> Result<T, E>,
    ) -> Result<T, E> {
        let lock = || self.entries.lock().unwrap_or_else(|p| p.into_inner());
        {
            let mut entries = lock();
            if let Some(k) = entries.iter().position(|(k, _)| *k == key) {
                let hit = entries.remove(k);
                let value = hit.1.clone();
                entries.push(hit);
                return Ok(value);
            }
        }
        let made = make()?;
        let mut entries = lock();
        if !entries.iter().any(|(k, _)| *k == key) {
            entries.push((key, made.clone()));
            if entries.len() > N {
                entries.remove(0);
            }
        }
        Ok(made)
    }

    /// [`Memo::get_or_make`] for a `make` that cannot fail.
    pub(crate) fn get_or(&self, key: K, make: impl FnOnce() -> T) -> T {
        let Ok(value) = self.get_or_make::<std::convert::Infallible>(key, || Ok(make()));
        value
    }

    /// Values held.
    #[cfg(test)]
    fn len(&self) -> usize {
        self.entries.lock().unwrap().len()
    }
}

/// A shared value as part of a key, compared by identity (`Arc::ptr_eq`); holding it keeps
/// its address from being reused while it is a key.
#[derive(Clone)]
pub(crate) struct Same<T>(pub(crate) Option<Arc<T>>);

impl<T> PartialEq for Same<T> {
    fn eq(&self, other: &Same<T>) -> bool {
        match (&self.0, &other.0) {
            (None, None) => true,
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_least_recently_used_entry_goes_first() {
        const N: usize = 64;
        let memo: Memo<String, usize, N> = Memo::new();
        let made = std::cell::Cell::new(0);
        let get = |k: &str, v: usize| {
            memo.get_or(k.to_owned(), || {
                made.set(made.get() + 1);
                v
            })
        };
        for k in 0..N {
            assert_eq!(get(&format!("k{k}"), k), k);
        }
        assert_eq!(made.get(), N);
        // k0 used again (not remade): k1 is now the least recently used.
        assert_eq!(get("k0", 999), 0);
        assert_eq!(made.get(), N);
        assert_eq!(get("new", 1000), 1000);
        assert_eq!(memo.len(), N);
        assert_eq!(get("k0", 999), 0, "k0 kept");
        assert_eq!(get("k1", 111), 111, "k1 dropped, so remade");
        // Many more keys keep the size bounded.
        for k in 0..10 * N {
            get(&format!("material/{k}"), k);
        }
        assert_eq!(memo.len(), N);
        // A failure is not kept.
        let failed: Result<usize, ()> = memo.get_or_make("bad".to_owned(), || Err(()));
        assert!(failed.is_err());
        assert_eq!(get("bad", 7), 7);
    }
}
