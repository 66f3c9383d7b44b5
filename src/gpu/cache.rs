//! What the GPU rasteriser made on a device (pipelines, layouts, generated materials, packed
//! textures), by what it was made from, so that frames after the first compile nothing. The
//! least recently used entries beyond [`ENTRIES`] are dropped: an editing session that
//! compiles a new material on every structural edit does not grow without bound.

use std::any::Any;
use std::collections::HashMap;
use std::sync::Arc;

/// Entries kept: the fixed kinds (scene pipelines per sample count, resolve, accumulate,
/// environment, scene textures) are about a dozen; the rest are materials.
pub(super) const ENTRIES: usize = 64;

/// A device's cache (see the module doc).
#[derive(Default)]
pub(crate) struct DeviceCache {
    entries: HashMap<String, (u64, Arc<dyn Any + Send + Sync>)>,
    clock: u64,
}

impl DeviceCache {
    /// The value under `key`, if it is there and a `T`; marks it used.
    pub(crate) fn get<T: Send + Sync + 'static>(&mut self, key: &str) -> Option<Arc<T>> {
        self.clock += 1;
        let (used, v) = self.entries.get_mut(key)?;
        *used = self.clock;
        v.clone().downcast::<T>().ok()
    }

    /// Keeps `value` under `key`, dropping the least recently used entry when full.
    pub(crate) fn insert<T: Send + Sync + 'static>(&mut self, key: &str, value: Arc<T>) {
        self.clock += 1;
        if self.entries.len() >= ENTRIES && !self.entries.contains_key(key) {
            let oldest = self
                .entries
                .iter()
                .min_by_key(|(_, (used, _))| *used)
                .map(|(k, _)| k.clone());
            if let Some(k) = oldest {
                self.entries.remove(&k);
            }
        }
        self.entries.insert(key.to_owned(), (self.clock, value));
    }

    /// Entries held.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.entries.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_least_recently_used_entry_goes_first() {
        let mut c = DeviceCache::default();
        for k in 0..ENTRIES {
            c.insert(&format!("k{k}"), Arc::new(k));
        }
        // k0 used again: k1 is now the oldest.
        assert_eq!(c.get::<usize>("k0").as_deref(), Some(&0));
        c.insert("new", Arc::new(1000usize));
        assert_eq!(c.len(), ENTRIES);
        assert!(c.get::<usize>("k1").is_none(), "k1 dropped");
        assert_eq!(c.get::<usize>("k0").as_deref(), Some(&0));
        assert_eq!(c.get::<usize>("new").as_deref(), Some(&1000));
        // A value of another type under a key is not returned as this one.
        assert!(c.get::<String>("k2").is_none());
        // Many more materials keep the size bounded.
        for k in 0..10 * ENTRIES {
            c.insert(&format!("material/{k}"), Arc::new(k));
        }
        assert_eq!(c.len(), ENTRIES);
    }
}
