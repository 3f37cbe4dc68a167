//! Picking an adapter and creating a device, honouring `WGPU_BACKEND` and
//! `WGPU_ADAPTER_NAME`.

use crate::DeviceError;
use crate::UncapturedErrors;

/// An adapter with its device and queue.
#[derive(Debug)]
pub struct Gpu {
    /// The adapter chosen.
    pub adapter: wgpu::Adapter,
    /// The device created on it.
    pub device: wgpu::Device,
    /// The device's queue.
    pub queue: wgpu::Queue,
    /// The device's errors that no error scope caught (see
    /// [`UncapturedErrors::install`]); the code that submits work takes
    /// them and returns them as its error.
    pub uncaptured: UncapturedErrors,
}

/// What to ask of the device.
#[derive(Clone, Debug, Default)]
pub struct DeviceRequest {
    /// Features the device must have; missing ones are an error.
    pub required_features: wgpu::Features,
    /// Features enabled when the adapter has them (for example timestamps).
    pub optional_features: wgpu::Features,
}

impl Gpu {
    /// Picks an adapter and creates a device with the adapter's own limits
    /// (larger buffers than the WebGPU defaults where the hardware allows),
    /// plus `TIMESTAMP_QUERY`, `MEMORY_DECORATION_COHERENT` and
    /// `PIPELINE_CACHE` when available,
    /// plus what `request` asks for. The device's uncaptured errors are
    /// recorded in [`Gpu::uncaptured`] instead of panicking.
    ///
    /// `WGPU_BACKEND` (e.g. `vulkan`) restricts the backends searched;
    /// `WGPU_ADAPTER_NAME` picks the first adapter whose name contains it
    /// (case-insensitive).
    pub fn new(request: &DeviceRequest) -> Result<Self, DeviceError> {
        pollster::block_on(Self::new_async(request))
    }

    async fn new_async(request: &DeviceRequest) -> Result<Self, DeviceError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = match std::env::var("WGPU_ADAPTER_NAME") {
            Ok(wanted) => {
                let adapters = instance.enumerate_adapters(wgpu::Backends::all()).await;
                let names: Vec<String> = adapters.iter().map(|a| a.get_info().name).collect();
                adapters
                    .into_iter()
                    .find(|a| {
                        a.get_info()
                            .name
                            .to_lowercase()
                            .contains(&wanted.to_lowercase())
                    })
                    .ok_or_else(|| {
                        DeviceError::NoAdapter(format!(
                            "WGPU_ADAPTER_NAME={wanted:?} matches none of {names:?}"
                        ))
                    })?
            }
            Err(_) => instance
                .request_adapter(&wgpu::RequestAdapterOptions {
                    power_preference: wgpu::PowerPreference::from_env()
                        .unwrap_or(wgpu::PowerPreference::HighPerformance),
                    ..Default::default()
                })
                .await
                .map_err(|e| DeviceError::NoAdapter(e.to_string()))?,
        };
        let available = adapter.features();
        if !available.contains(request.required_features) {
            return Err(DeviceError::RequestDevice(format!(
                "adapter `{}` lacks required features {:?}",
                adapter.get_info().name,
                request.required_features - available
            )));
        }
        let wanted = request.required_features
            | ((request.optional_features
                | wgpu::Features::TIMESTAMP_QUERY
                | wgpu::Features::MEMORY_DECORATION_COHERENT
                | wgpu::Features::PIPELINE_CACHE)
                & available);
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("scheduler device"),
                required_features: wanted,
                required_limits: adapter.limits(),
                ..Default::default()
            })
            .await
            .map_err(|e| DeviceError::RequestDevice(e.to_string()))?;
        let uncaptured = UncapturedErrors::install(&device);
        Ok(Self {
            adapter,
            device,
            queue,
            uncaptured,
        })
    }

    /// A one-line description of the adapter, for reports.
    pub fn describe(&self) -> String {
        let info = self.adapter.get_info();
        format!(
            "{} ({:?}, {:?}, driver {} {})",
            info.name, info.device_type, info.backend, info.driver, info.driver_info
        )
    }
}
