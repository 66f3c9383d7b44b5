//! Frame resources lent out and taken back: the render targets and read-back buffers of a GPU
//! frame, kept after the frame for the next one of the same size.
//!
//! A frame of the rasteriser allocates its colour, depth and material targets, the resolved
//! pixels and a staging buffer: about 60 MB at 1024². Made fresh every frame, the driver's
//! allocations are paged in again each time (on lavapipe the kernel zeroed every page, and
//! the frame took 17 ms longer: `fresnel_glass` at 1024², best of 16, 90 → 74 ms). A
//! [`Lent`] resource goes back to the pool when dropped, so two frames drawn at once (two
//! threads on one device) never share a target; a later frame that takes it back writes it
//! only in a later submission, after the earlier frame's work on the one queue.

use std::sync::Mutex;

/// The most bytes a pool keeps free by default; the least recently returned go first
/// beyond it.
pub(super) const MAX_FREE_BYTES: u64 = 256 << 20;

/// What a resource was made as; one is lent again only for the same description.
#[derive(Clone, Debug, PartialEq)]
enum Kind {
    /// Width, height, sample count, format, usage.
    Texture(u32, u32, u32, wgpu::TextureFormat, wgpu::TextureUsages),
    /// Size, usage.
    Buffer(u64, wgpu::BufferUsages),
}

/// A pooled resource.
#[derive(Debug)]
pub(super) enum Resource {
    Texture(wgpu::Texture),
    Buffer(wgpu::Buffer),
}

/// The free resources of one device, least recently returned first.
pub(super) struct Pool {
    free: Mutex<Vec<(Kind, u64, Resource)>>,
    max_free_bytes: u64,
}

impl Default for Pool {
    fn default() -> Pool {
        Pool::with_bound(MAX_FREE_BYTES)
    }
}

/// A resource lent by a [`Pool`], given back when dropped.
pub(super) struct Lent<'a, T: Pooled> {
    pool: &'a Pool,
    kind: Kind,
    bytes: u64,
    value: Option<T>,
}

impl<T: Pooled> std::ops::Deref for Lent<'_, T> {
    type Target = T;
    fn deref(&self) -> &T {
        self.value.as_ref().expect("lent until dropped")
    }
}

impl<T: Pooled> Lent<'_, T> {
    /// Drops the resource without giving it back (a buffer whose mapping failed half way,
    /// which may still be mapped).
    pub(super) fn forget(mut self) {
        self.value = None;
    }
}

/// A resource a [`Lent`] can hold.
pub(super) trait Pooled: Sized {
    /// As the pool holds it.
    fn into_resource(self) -> Resource;
}

impl Pooled for wgpu::Texture {
    fn into_resource(self) -> Resource {
        Resource::Texture(self)
    }
}

impl Pooled for wgpu::Buffer {
    fn into_resource(self) -> Resource {
        Resource::Buffer(self)
    }
}

impl<T: Pooled> Drop for Lent<'_, T> {
    fn drop(&mut self) {
        if let Some(v) = self.value.take() {
            self.pool
                .give_back(self.kind.clone(), self.bytes, v.into_resource());
        }
    }
}

impl Pool {
    /// An empty pool that keeps at most `max_free_bytes` free.
    pub(super) fn with_bound(max_free_bytes: u64) -> Pool {
        Pool {
            free: Mutex::new(Vec::new()),
            max_free_bytes,
        }
    }

    /// A free resource of `kind`, taken out of the pool.
    fn take(&self, kind: &Kind) -> Option<Resource> {
        let mut free = self.free.lock().unwrap_or_else(|p| p.into_inner());
        let k = free.iter().rposition(|(k, _, _)| k == kind)?;
        Some(free.remove(k).2)
    }

    fn give_back(&self, kind: Kind, bytes: u64, r: Resource) {
        let mut free = self.free.lock().unwrap_or_else(|p| p.into_inner());
        free.push((kind, bytes, r));
        let mut total: u64 = free.iter().map(|e| e.1).sum();
        while total > self.max_free_bytes && !free.is_empty() {
            total -= free.remove(0).1;
        }
    }

    /// Bytes held free.
    #[cfg(test)]
    fn free_bytes(&self) -> u64 {
        self.free.lock().unwrap().iter().map(|e| e.1).sum()
    }

    /// A 2D texture of one level as `desc` says (its label that of the first frame that
    /// made it).
    pub(super) fn texture(
        &self,
        device: &wgpu::Device,
        desc: &wgpu::TextureDescriptor,
    ) -> Lent<'_, wgpu::Texture> {
        debug_assert_eq!(desc.mip_level_count, 1);
        let (w, h) = (desc.size.width, desc.size.height);
        let kind = Kind::Texture(w, h, desc.sample_count, desc.format, desc.usage);
        let texel = desc.format.block_copy_size(None).unwrap_or(16) as u64;
        let bytes = w as u64 * h as u64 * desc.sample_count as u64 * texel;
        let value = match self.take(&kind) {
            Some(Resource::Texture(t)) => t,
            _ => device.create_texture(desc),
        };
        Lent {
            pool: self,
            kind,
            bytes,
            value: Some(value),
        }
    }

    /// A buffer of `size` bytes (already aligned) and `usage`.
    pub(super) fn buffer(
        &self,
        device: &wgpu::Device,
        label: &str,
        size: u64,
        usage: wgpu::BufferUsages,
    ) -> Lent<'_, wgpu::Buffer> {
        let kind = Kind::Buffer(size, usage);
        let value = match self.take(&kind) {
            Some(Resource::Buffer(b)) => b,
            _ => device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            }),
        };
        Lent {
            pool: self,
            kind,
            bytes: size,
            value: Some(value),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn device() -> Option<wgpu::Device> {
        let ctx = crate::gpu::GpuContext::shared().ok()?;
        Some(ctx.state.device.clone())
    }

    fn desc(side: u32) -> wgpu::TextureDescriptor<'static> {
        wgpu::TextureDescriptor {
            label: Some("pool test"),
            size: wgpu::Extent3d {
                width: side,
                height: side,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Float,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        }
    }

    #[test]
    fn a_returned_resource_is_lent_again_only_for_its_own_description() {
        let Some(device) = device() else {
            eprintln!(
                "SKIPPED a_returned_resource_is_lent_again_only_for_its_own_description: no GPU adapter"
            );
            return;
        };
        let pool = Pool::default();
        let first = pool.texture(&device, &desc(64));
        // Lent out: a second frame of the same size gets another texture.
        let second = pool.texture(&device, &desc(64));
        assert!(*first != *second);
        let ids = [(*first).clone(), (*second).clone()];
        drop(first);
        drop(second);
        assert_eq!(pool.free_bytes(), 2 * 64 * 64 * 16);
        // Back: the same size gets one of them, another size a new one.
        let again = pool.texture(&device, &desc(64));
        assert!(ids.contains(&*again));
        let other = pool.texture(&device, &desc(32));
        assert!(!ids.contains(&*other));
        assert_eq!(pool.free_bytes(), 64 * 64 * 16);
        // Buffers by size and usage; a forgotten one is not given back.
        let usage = wgpu::BufferUsages::STORAGE;
        let b = pool.buffer(&device, "pool test", 256, usage);
        let kept = (*b).clone();
        drop(b);
        let b = pool.buffer(&device, "pool test", 256, usage);
        assert!(*b == kept);
        assert!(*pool.buffer(&device, "pool test", 512, usage) != kept);
        b.forget();
        assert!(*pool.buffer(&device, "pool test", 256, usage) != kept);
    }

    #[test]
    fn the_pool_keeps_at_most_its_byte_bound() {
        let Some(device) = device() else {
            eprintln!("SKIPPED the_pool_keeps_at_most_its_byte_bound: no GPU adapter");
            return;
        };
        let pool = Pool::with_bound(1024);
        let usage = wgpu::BufferUsages::STORAGE;
        let lent: Vec<_> = (0..6)
            .map(|_| pool.buffer(&device, "pool test", 256, usage))
            .collect();
        let newest = (*lent[5]).clone();
        drop(lent);
        assert_eq!(pool.free_bytes(), 1024);
        // The last four returned are kept: the newest is lent first.
        assert!(*pool.buffer(&device, "pool test", 256, usage) == newest);
    }
}
