//! Frame sequences: the times of `render --frames N --fps F` and the animated PNG (APNG)
//! that holds them.
//!
//! Frame k is rendered at `t0 + k/F` (worked out in f64, rounded to f32 once), so frame k of
//! a sequence is the still rendered at that `--time`. The animation is an APNG: it keeps the
//! renders' 8-bit RGB colour exactly (a GIF has a 256-colour palette, which bands the smooth
//! shading of a material ball), every frame is shown for 1/F seconds, it loops forever, and
//! a viewer without APNG support shows frame 0. Encoded in memory with the `png` crate
//! (already a dependency of `image`); no time stamps, so the same frames give the same bytes.

use super::sheet::Rgb8Image;
use std::sync::{Arc, Mutex};

/// The most frames one sequence may have (four-digit frame numbers).
pub const MAX_FRAMES: u32 = 10_000;
/// The lowest frame rate accepted, frames per second (a frame shown 1000 s at most).
pub const MIN_FPS: f32 = 0.001;
/// The highest frame rate accepted, frames per second.
pub const MAX_FPS: f32 = 1000.0;

/// Why a frame sequence cannot be made.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum FramesError {
    /// `--frames` is 0 or above [`MAX_FRAMES`].
    #[error("--frames {0}: the number of frames must be 1 to {MAX_FRAMES}")]
    FrameCount(u32),
    /// `--fps` is not a finite number in [[`MIN_FPS`], [`MAX_FPS`]].
    #[error(
        "--fps {0}: the frame rate must be a number from {MIN_FPS} to {MAX_FPS} frames per second"
    )]
    Fps(f32),
    /// The first time is not finite.
    #[error("--time {0}: the start time must be a finite number of seconds")]
    Start(f32),
    /// A frame pushed to the animation is not the animation's size.
    #[error("frame {frame} is {got_w}x{got_h}, the animation is {width}x{height}")]
    Size {
        /// Index of the frame.
        frame: u32,
        /// The animation's width.
        width: u32,
        /// The animation's height.
        height: u32,
        /// The frame's width.
        got_w: u32,
        /// The frame's height.
        got_h: u32,
    },
    /// More or fewer frames were pushed than announced.
    #[error("the animation announced {expected} frames and got {got}")]
    Pushed {
        /// Frames announced.
        expected: u32,
        /// Frames pushed.
        got: u32,
    },
    /// The PNG encoder failed.
    #[error("cannot encode the animation: {0}")]
    Encode(String),
}

/// A validated frame count and rate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frames {
    /// Number of frames, 1 to [`MAX_FRAMES`].
    pub count: u32,
    /// Frames per second, [`MIN_FPS`] to [`MAX_FPS`].
    pub fps: f32,
}

impl Frames {
    /// Checks `count` and `fps`.
    pub fn new(count: u32, fps: f32) -> Result<Frames, FramesError> {
        if count == 0 || count > MAX_FRAMES {
            return Err(FramesError::FrameCount(count));
        }
        if !(fps.is_finite() && (MIN_FPS..=MAX_FPS).contains(&fps)) {
            return Err(FramesError::Fps(fps));
        }
        Ok(Frames { count, fps })
    }

    /// The time of frame `k`: `t0 + k/fps`, in f64 and rounded to f32 once.
    pub fn time(&self, t0: f32, k: u32) -> f32 {
        (t0 as f64 + k as f64 / self.fps as f64) as f32
    }

    /// The times of every frame from `t0`.
    pub fn times(&self, t0: f32) -> Result<Vec<f32>, FramesError> {
        if !t0.is_finite() {
            return Err(FramesError::Start(t0));
        }
        Ok((0..self.count).map(|k| self.time(t0, k)).collect())
    }

    /// The APNG frame delay `numerator / denominator` seconds closest to 1/fps (both at most
    /// 65535; exact for integer rates).
    pub fn delay(&self) -> (u16, u16) {
        let d = 1.0 / self.fps as f64;
        let mut best = (1u16, 1u16);
        let mut best_err = f64::INFINITY;
        for den in 1..=u16::MAX {
            let num = (d * den as f64).round().clamp(1.0, u16::MAX as f64);
            let err = (num / den as f64 - d).abs();
            if err < best_err {
                best = (num as u16, den);
                best_err = err;
                if err == 0.0 {
                    break;
                }
            }
        }
        best
    }

    /// The numbered still of frame `k` beside `path`: `name.png` → `name_0007.png`.
    pub fn numbered(path: &std::path::Path, k: u32) -> std::path::PathBuf {
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("frame");
        let ext = path.extension().and_then(|s| s.to_str()).unwrap_or("png");
        path.with_file_name(format!("{stem}_{k:04}.{ext}"))
    }
}

/// The in-memory file the encoder writes to, shared so that its bytes outlive the encoder.
#[derive(Clone, Default)]
struct Sink(Arc<Mutex<Vec<u8>>>);

impl std::io::Write for Sink {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let mut bytes = self
            .0
            .lock()
            .map_err(|_| std::io::Error::other("poisoned"))?;
        bytes.extend_from_slice(buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// An APNG being built in memory, one RGB8 frame at a time.
pub struct Apng {
    writer: png::Writer<Sink>,
    sink: Sink,
    width: u32,
    height: u32,
    expected: u32,
    pushed: u32,
}

impl Apng {
    /// Starts an animation of `frames` frames of `width × height`, looping forever.
    pub fn new(width: u32, height: u32, frames: &Frames) -> Result<Apng, FramesError> {
        let enc_err = |e: png::EncodingError| FramesError::Encode(e.to_string());
        let sink = Sink::default();
        let mut encoder = png::Encoder::new(sink.clone(), width, height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        encoder.set_animated(frames.count, 0).map_err(enc_err)?;
        let (num, den) = frames.delay();
        encoder.set_frame_delay(num, den).map_err(enc_err)?;
        let writer = encoder.write_header().map_err(enc_err)?;
        Ok(Apng {
            writer,
            sink,
            width,
            height,
            expected: frames.count,
            pushed: 0,
        })
    }

    /// Appends the next frame.
    pub fn push(&mut self, image: &Rgb8Image) -> Result<(), FramesError> {
        if (image.width, image.height) != (self.width, self.height) {
            return Err(FramesError::Size {
                frame: self.pushed,
                width: self.width,
                height: self.height,
                got_w: image.width,
                got_h: image.height,
            });
        }
        if self.pushed == self.expected {
            return Err(FramesError::Pushed {
                expected: self.expected,
                got: self.pushed + 1,
            });
        }
        self.writer
            .write_image_data(image.pixels.as_flattened())
            .map_err(|e| FramesError::Encode(e.to_string()))?;
        self.pushed += 1;
        Ok(())
    }

    /// The file's bytes, once every announced frame has been pushed.
    pub fn finish(self) -> Result<Vec<u8>, FramesError> {
        if self.pushed != self.expected {
            return Err(FramesError::Pushed {
                expected: self.expected,
                got: self.pushed,
            });
        }
        self.writer
            .finish()
            .map_err(|e| FramesError::Encode(e.to_string()))?;
        let mut bytes = self
            .sink
            .0
            .lock()
            .map_err(|_| FramesError::Encode("poisoned buffer".to_owned()))?;
        Ok(std::mem::take(&mut *bytes))
    }
}
