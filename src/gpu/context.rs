//! The headless wgpu device: adapter selection and the process-wide shared context.

use super::device::DeviceState;
use crate::plan::EvalError;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

/// A headless wgpu device and queue, on any adapter (hardware, or a software fallback such
/// as lavapipe).
pub struct GpuContext {
    _instance: wgpu::Instance,
    adapter: wgpu::Adapter,
    pub(super) state: Arc<DeviceState>,
}

impl std::fmt::Debug for GpuContext {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuContext")
            .field("adapter", &self.adapter_info())
            .finish_non_exhaustive()
    }
}

impl GpuContext {
    /// Opens the first usable adapter (Vulkan, Metal or DX12 first, then OpenGL) and creates a
    /// device with the adapter's limits; `EvalError::Gpu("no GPU adapter: ...")` if none.
    ///
    /// `WGPU_BACKEND` (e.g. `vulkan`, `gl`) restricts the backends tried.
    pub fn new() -> Result<GpuContext, EvalError> {
        let attempts: Vec<wgpu::Backends> = match wgpu::Backends::from_env() {
            Some(b) => vec![b],
            None => vec![wgpu::Backends::PRIMARY, wgpu::Backends::SECONDARY],
        };
        let mut why = Vec::new();
        for backends in attempts {
            let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
            desc.backends = backends;
            let instance = wgpu::Instance::new(desc);
            let options = wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: None,
                apply_limit_buckets: false,
            };
            match pollster::block_on(instance.request_adapter(&options)) {
                Ok(adapter) => return GpuContext::open(instance, adapter),
                Err(e) => why.push(format!("{backends:?}: {e}")),
            }
        }
        Err(EvalError::Gpu(format!(
            "no GPU adapter: {}",
            why.join("; ")
        )))
    }

    fn open(instance: wgpu::Instance, adapter: wgpu::Adapter) -> Result<GpuContext, EvalError> {
        let info = adapter.get_info();
        let desc = wgpu::DeviceDescriptor {
            label: Some("matgraph"),
            // Rgba32Float multisampling for the GPU rasteriser, where the adapter has it.
            // and the primitive index its fragment stages rebuild barycentrics from.
            required_features: adapter.features()
                & (wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES
                    | wgpu::Features::PRIMITIVE_INDEX),
            required_limits: adapter.limits(),
            ..Default::default()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&desc)).map_err(|e| {
            EvalError::Gpu(format!(
                "no GPU adapter: {} ({:?}) refused a device: {e}",
                info.name, info.backend
            ))
        })?;
        let uncaptured = Arc::new(Mutex::new(Vec::new()));
        let sink = uncaptured.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            sink.lock()
                .unwrap_or_else(|p| p.into_inner())
                .push(e.to_string());
        }));
        let lost = Arc::new(Mutex::new(None));
        let flag = lost.clone();
        device.set_device_lost_callback(move |reason, message| {
            *flag.lock().unwrap_or_else(|p| p.into_inner()) =
                Some(format!("{reason:?}: {message}"));
        });
        let state = Arc::new(DeviceState {
            device,
            queue,
            uncaptured,
            lost,
            pipelines: AtomicUsize::new(0),
            cache: crate::memo::Memo::new(),
            uploads: crate::memo::Memo::new(),
            small_uploads: crate::memo::Memo::new(),
            pool: Default::default(),
            meshes: crate::memo::Memo::new(),
            scenes: crate::memo::Memo::new(),
            drawn_scenes: crate::memo::Memo::new(),
            serial: (info.backend == wgpu::Backend::Gl)
                .then(|| parking_lot::ReentrantMutex::new(())),
        });
        Ok(GpuContext {
            _instance: instance,
            adapter,
            state,
        })
    }

    /// The process-wide context, created on first use (creating devices is slow); the error
    /// is remembered too, so a machine without an adapter is probed once.
    pub fn shared() -> Result<&'static GpuContext, EvalError> {
        static SHARED: OnceLock<Result<GpuContext, EvalError>> = OnceLock::new();
        SHARED
            .get_or_init(GpuContext::new)
            .as_ref()
            .map_err(Clone::clone)
    }

    /// The adapter's name, type, backend and driver.
    pub fn adapter_info(&self) -> wgpu::AdapterInfo {
        self.adapter.get_info()
    }

    /// One line describing the adapter, for reports: `name (type, backend, driver info)`.
    pub fn describe(&self) -> String {
        let i = self.adapter_info();
        format!(
            "{} ({:?}, {:?}, {} {})",
            i.name, i.device_type, i.backend, i.driver, i.driver_info
        )
    }

    /// What the adapter supports for `format` (sample counts, usages).
    pub(super) fn format_features(
        &self,
        format: wgpu::TextureFormat,
    ) -> wgpu::TextureFormatFeatures {
        self.adapter.get_texture_format_features(format)
    }

    /// The device's features.
    pub fn features(&self) -> wgpu::Features {
        self.state.device.features()
    }

    /// The device's limits.
    pub fn limits(&self) -> wgpu::Limits {
        self.state.device.limits()
    }

    /// The wgpu device.
    pub fn device(&self) -> &wgpu::Device {
        &self.state.device
    }

    /// The wgpu queue.
    pub fn queue(&self) -> &wgpu::Queue {
        &self.state.queue
    }

    /// Compute pipelines created on this context so far, by every plan and harness.
    pub fn pipelines_created(&self) -> usize {
        self.state.pipelines.load(Ordering::Relaxed)
    }
}
