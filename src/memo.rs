//! Memos: the last few values made from a key, for the tables and textures that the
//! frames of an animation or the editor's preview would otherwise remake on every frame.

use std::sync::{Arc, Mutex};

/// The values made for the last `N` keys (the oldest is dropped first).
pub(crate) struct Memo<K, T, const N: usize> {
    entries: Mutex<Vec<(K, T)>>,
}

impl<K: PartialEq, T: Clone, const N: usize> Memo<K, T, N> {
    /// An empty cache.
    pub(crate) const fn new() -> Self {
        Memo {
            entries: Mutex::new(Vec::new()),
        }
    }

    /// The value for `key`, made (outside the lock) and kept if it is missing.
    pub(crate) fn get_or_make<E>(
        &self,
        key: K,
        make: impl FnOnce() -> Result<T, E>,
    ) -> Result<T, E> {
        let lock = || self.entries.lock().unwrap_or_else(|p| p.into_inner());
        if let Some((_, t)) = lock().iter().find(|(k, _)| *k == key) {
            return Ok(t.clone());
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
