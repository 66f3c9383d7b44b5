//! Image thumbnails for the texture picker and the texture nodes: an image decoded with
//! [`crate::image_io::load_image`] (its file type's default colour space, as it looks),
//! box-filtered down to at most [`THUMB_SIDE`] texels a side and encoded to sRGB8, cached
//! by path, length and modification time. Decoding runs on a worker thread of its own and
//! only for what is asked (the browser asks for the rows on screen), so a folder of large
//! images lists at once and fills in; an image saved again is decoded again.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::SystemTime;

/// The longest side of a thumbnail, texels.
pub const THUMB_SIDE: u32 = 48;

/// The most thumbnails kept (the least recently asked for go first).
pub const CAPACITY: usize = 256;

/// What a file was when it was decoded: its length and modification time.
pub type Stamp = (u64, Option<SystemTime>);

/// A decoded thumbnail.
#[derive(Clone)]
pub struct Thumb {
    /// The image's width, texels.
    pub width: u32,
    /// The image's height, texels.
    pub height: u32,
    /// The thumbnail's size (width, height), at most [`THUMB_SIDE`] a side.
    pub size: [usize; 2],
    /// Its sRGB8 RGBA texels, row by row.
    pub rgba: Vec<u8>,
    /// Its egui texture, made when first drawn.
    texture: Option<egui::TextureHandle>,
}

impl std::fmt::Debug for Thumb {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Thumb({}×{} → {:?})", self.width, self.height, self.size)
    }
}

/// What the cache holds for a file.
#[derive(Clone, Debug)]
pub enum Status<'a> {
    /// Being decoded.
    Pending,
    /// Decoded.
    Ready(&'a Thumb),
    /// Missing, unreadable or not decodable: why.
    Failed(&'a str),
}

/// A cache entry.
enum Slot {
    Pending,
    Ready(Box<Thumb>),
    Failed(String),
}

struct Entry {
    stamp: Stamp,
    slot: Slot,
    /// When it was last asked for (the cache's counter).
    used: u64,
}

/// A decode to do: the file and the stamp it had when asked for.
type Job = (PathBuf, Stamp);

/// A decode done.
type Done = (PathBuf, Stamp, Result<Thumb, String>);

/// The thumbnail cache, with its decoding worker (started on the first request).
pub struct Thumbnails {
    entries: HashMap<PathBuf, Entry>,
    jobs: Option<mpsc::Sender<Job>>,
    done: Option<mpsc::Receiver<Done>>,
    /// Decodes started, all told.
    decodes: usize,
    clock: u64,
}

impl Default for Thumbnails {
    fn default() -> Self {
        Thumbnails::new()
    }
}

impl Thumbnails {
    /// An empty cache (no worker yet).
    pub fn new() -> Thumbnails {
        Thumbnails {
            entries: HashMap::new(),
            jobs: None,
            done: None,
            decodes: 0,
            clock: 0,
        }
    }

    /// How many decodes were started (a path asked for again with the same stamp starts
    /// none).
    pub fn decodes(&self) -> usize {
        self.decodes
    }

    /// Whether a decode is under way.
    pub fn pending(&self) -> bool {
        self.entries
            .values()
            .any(|e| matches!(e.slot, Slot::Pending))
    }

    /// How many thumbnails (and failures) are kept.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether nothing is kept.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Takes the decodes the worker finished.
    pub fn poll(&mut self) {
        let Some(done) = &self.done else {
            return;
        };
        while let Ok((path, stamp, result)) = done.try_recv() {
            // A file changed while it was decoded: its entry asks again.
            if let Some(e) = self.entries.get_mut(&path).filter(|e| e.stamp == stamp) {
                e.slot = match result {
                    Ok(t) => Slot::Ready(Box::new(t)),
                    Err(m) => Slot::Failed(m),
                };
            }
        }
    }

    /// The thumbnail of `path`: decoded once per [`Stamp`] (the file is looked at each
    /// time, its image decoded only when new or changed, on the worker); a file that
    /// cannot be looked at fails at once.
    pub fn get(&mut self, path: &Path) -> Status<'_> {
        self.poll();
        self.clock += 1;
        let stamp = match std::fs::metadata(path) {
            Ok(m) => (m.len(), m.modified().ok()),
            Err(e) => {
                let message = match e.kind() {
                    std::io::ErrorKind::NotFound => "missing".to_owned(),
                    _ => e.to_string(),
                };
                self.insert(path, (0, None), Slot::Failed(message));
                return self.status(path);
            }
        };
        let fresh = self.entries.get(path).is_some_and(|e| e.stamp == stamp);
        if !fresh {
            self.insert(path, stamp, Slot::Pending);
            self.decodes += 1;
            let job = (path.to_owned(), stamp);
            let sent = self.worker().send(job.clone());
            if sent.is_err() {
                // The worker is gone (it panicked): decode here.
                self.jobs = None;
                let result = thumbnail(&job.0);
                self.insert(
                    path,
                    stamp,
                    match result {
                        Ok(t) => Slot::Ready(Box::new(t)),
                        Err(m) => Slot::Failed(m),
                    },
                );
            }
        }
        if let Some(e) = self.entries.get_mut(path) {
            e.used = self.clock;
        }
        self.status(path)
    }

    /// The texture of a ready thumbnail of `path` (made on first use) with the image's
    /// size; `None` while it is not ready.
    pub fn texture(
        &mut self,
        ctx: &egui::Context,
        path: &Path,
    ) -> Option<(egui::TextureId, egui::Vec2, [u32; 2])> {
        let e = self.entries.get_mut(path)?;
        let Slot::Ready(t) = &mut e.slot else {
            return None;
        };
        let handle = t.texture.get_or_insert_with(|| {
            let image = egui::ColorImage::from_rgba_unmultiplied(t.size, &t.rgba);
            ctx.load_texture(
                format!("thumbnail:{}", path.display()),
                image,
                egui::TextureOptions::LINEAR,
            )
        });
        let size = egui::vec2(t.size[0] as f32, t.size[1] as f32);
        Some((handle.id(), size, [t.width, t.height]))
    }

    fn status(&self, path: &Path) -> Status<'_> {
        match self.entries.get(path).map(|e| &e.slot) {
            Some(Slot::Ready(t)) => Status::Ready(t),
            Some(Slot::Failed(m)) => Status::Failed(m),
            Some(Slot::Pending) | None => Status::Pending,
        }
    }

    fn insert(&mut self, path: &Path, stamp: Stamp, slot: Slot) {
        if self.entries.len() >= CAPACITY && !self.entries.contains_key(path) {
            let oldest = self
                .entries
                .iter()
                .filter(|(_, e)| !matches!(e.slot, Slot::Pending))
                .min_by_key(|(_, e)| e.used)
                .map(|(p, _)| p.clone());
            if let Some(p) = oldest {
                self.entries.remove(&p);
            }
        }
        let used = self.clock;
        self.entries
            .insert(path.to_owned(), Entry { stamp, slot, used });
    }

    /// The worker's queue, started on first use.
    fn worker(&mut self) -> &mpsc::Sender<Job> {
        self.jobs.get_or_insert_with(|| {
            let (jobs, queue) = mpsc::channel::<Job>();
            let (results, done) = mpsc::channel::<Done>();
            std::thread::Builder::new()
                .name("matgraph-thumbnails".into())
                .spawn(move || {
                    for (path, stamp) in queue {
                        let result = thumbnail(&path);
                        if results.send((path, stamp, result)).is_err() {
                            return;
                        }
                    }
                })
                .expect("a thread can be spawned");
            self.done = Some(done);
            jobs
        })
    }
}

/// The editor's cache, kept in the egui context's memory (one per window or test harness).
pub fn shared(ctx: &egui::Context) -> Arc<Mutex<Thumbnails>> {
    let id = egui::Id::new("matgraph-thumbnails");
    ctx.data_mut(|d| {
        d.get_temp_mut_or_insert_with(id, || Arc::new(Mutex::new(Thumbnails::new())))
            .clone()
    })
}

/// Decodes `path` and makes its thumbnail; the error's text without the path.
pub fn thumbnail(path: &Path) -> Result<Thumb, String> {
    let image = crate::image_io::load_image(path).map_err(|e| match e {
        crate::texture::TextureError::File { message, .. } => message,
        e => e.to_string(),
    })?;
    let (width, height) = (image.width, image.height);
    let [tw, th] = thumb_size(width, height);
    let rgba = downscale(&image, tw, th)
        .into_iter()
        .flat_map(|[r, g, b, a]| {
            let enc =
                |c: f32| (crate::image_io::linear_to_srgb(c.clamp(0.0, 1.0)) * 255.0).round() as u8;
            [
                enc(r),
                enc(g),
                enc(b),
                (a.clamp(0.0, 1.0) * 255.0).round() as u8,
            ]
        })
        .collect();
    Ok(Thumb {
        width,
        height,
        size: [tw as usize, th as usize],
        rgba,
        texture: None,
    })
}

/// The thumbnail size of a `width` × `height` image: the longer side [`THUMB_SIDE`] (or
/// the image's, if smaller), the other in proportion, at least 1.
pub fn thumb_size(width: u32, height: u32) -> [u32; 2] {
    let long = width.max(height).max(1);
    if long <= THUMB_SIDE {
        return [width.max(1), height.max(1)];
    }
    let scale = |s: u32| {
        ((u64::from(s) * u64::from(THUMB_SIDE) + u64::from(long) / 2) / u64::from(long)).max(1)
            as u32
    };
    [scale(width), scale(height)]
}

/// `image` box-filtered to `tw` × `th` texels (linear values): each texel the mean of the
/// source texels whose centres fall in its footprint (at least the nearest one).
pub fn downscale(image: &crate::texture::Image, tw: u32, th: u32) -> Vec<[f32; 4]> {
    let (w, h) = (image.width, image.height);
    // The source texels [start, end) of thumbnail texel k of n along a side of s.
    let span = |k: u32, n: u32, s: u32| {
        let start = (u64::from(k) * u64::from(s) / u64::from(n)) as u32;
        let end = ((u64::from(k) + 1) * u64::from(s) / u64::from(n)) as u32;
        (start.min(s - 1), end.max(start + 1).min(s))
    };
    let mut out = Vec::with_capacity((tw * th) as usize);
    for ty in 0..th {
        let (y0, y1) = span(ty, th, h);
        for tx in 0..tw {
            let (x0, x1) = span(tx, tw, w);
            let mut sum = [0.0f64; 4];
            for y in y0..y1 {
                for x in x0..x1 {
                    let t = image.texel(x, y);
                    for c in 0..4 {
                        sum[c] += f64::from(t[c]);
                    }
                }
            }
            let n = f64::from((x1 - x0) * (y1 - y0));
            out.push(sum.map(|s| (s / n) as f32));
        }
    }
    out
}
