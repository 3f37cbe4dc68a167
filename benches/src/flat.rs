//! The flat dispatch: one thread per item id, no queues. It does exactly the
//! per-item work of the spawn tree and is the floor on scheduling overhead.

use std::time::{Duration, Instant};

use scheduler::{bytemuck, wgpu};

use crate::gpu::{block_on, out_buffer};
use crate::timing::{TimeSource, timestamp_delta};
use crate::workload::{FLAT_WORKGROUP_SIZE, HASH_WGSL, Workload};
use crate::{BenchError, verify};

/// The flat kernel's own WGSL (bindings and entry point).
pub const FLAT_WGSL: &str = include_str!("../../shaders/benches/flat.wgsl");

const TIMEOUT: Duration = Duration::from_secs(60);

/// Timestamp queries around one compute pass.
#[derive(Debug)]
pub(crate) struct Timestamps {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    period_ns: f64,
}

impl Timestamps {
    /// The queries, when the device has `TIMESTAMP_QUERY`.
    pub(crate) fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Option<Self> {
        device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
            .then(|| Self {
                queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("flat timestamps"),
                    ty: wgpu::QueryType::Timestamp,
                    count: 2,
                }),
                resolve: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("flat timestamp resolve"),
                    size: 16,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                }),
                readback: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("flat timestamp read-back"),
                    size: 16,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
                period_ns: f64::from(queue.get_timestamp_period()),
            })
    }
}

/// A compute pipeline for `wgsl`'s entry point `flat_main`, with the
/// megakernel's runtime checks: bounds checks on, naga's loop bounding off
/// (scheduler/src/runtime/executor.rs), so that the same WGSL compiles to the
/// same machine code in both. Call it inside a validation error scope.
pub(crate) fn trusted_pipeline(
    device: &wgpu::Device,
    label: &str,
    wgsl: String,
) -> wgpu::ComputePipeline {
    #[expect(
        unsafe_code,
        reason = "same runtime checks as the megakernel: bounds checks on, loop bounding off; the flat kernels' loops are bounded"
    )]
    let module = unsafe {
        device.create_shader_module_trusted(
            wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(wgsl.into()),
            },
            wgpu::ShaderRuntimeChecks {
                bounds_checks: true,
                force_loop_bounding: false,
                ..wgpu::ShaderRuntimeChecks::checked()
            },
        )
    };
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: None,
        module: &module,
        entry_point: Some("flat_main"),
        compilation_options: Default::default(),
        cache: None,
    })
}

/// A flat kernel ready to dispatch: its pipeline, its one output buffer of
/// `words` u32s at binding 0, and the bind group holding it.
pub(crate) struct BoundKernel {
    pub pipeline: wgpu::ComputePipeline,
    pub out: wgpu::Buffer,
    pub bind_group: wgpu::BindGroup,
}

impl BoundKernel {
    /// Builds `wgsl` with [`trusted_pipeline`] and binds a fresh output
    /// buffer of `words` u32s; validation errors come back as
    /// [`BenchError::Gpu`].
    pub(crate) fn new(
        device: &wgpu::Device,
        label: &str,
        wgsl: String,
        words: u32,
    ) -> Result<Self, BenchError> {
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let pipeline = trusted_pipeline(device, label, wgsl);
        let out = out_buffer(device, words, label);
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: out.as_entire_binding(),
            }],
        });
        if let Some(error) = block_on(scope.pop()) {
            return Err(BenchError::Gpu(error.to_string()));
        }
        Ok(Self {
            pipeline,
            out,
            bind_group,
        })
    }
}

/// Runs one dispatch of `workgroups` and returns its time (GPU timestamps
/// around the pass with `timestamps`, else wall time) and the host wall time
/// from submission to completion.
pub(crate) fn dispatch_timed(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    pipeline: &wgpu::ComputePipeline,
    bind_group: &wgpu::BindGroup,
    workgroups: [u32; 3],
    timestamps: Option<&Timestamps>,
) -> Result<(Duration, Duration), BenchError> {
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("flat kernel"),
    });
    {
        let timestamp_writes = timestamps.map(|t| wgpu::ComputePassTimestampWrites {
            query_set: &t.queries,
            beginning_of_pass_write_index: Some(0),
            end_of_pass_write_index: Some(1),
        });
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("flat kernel"),
            timestamp_writes,
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        let [x, y, z] = workgroups;
        pass.dispatch_workgroups(x, y, z);
    }
    if let Some(t) = timestamps {
        encoder.resolve_query_set(&t.queries, 0..2, &t.resolve, 0);
        encoder.copy_buffer_to_buffer(&t.resolve, 0, &t.readback, 0, 16);
    }
    let command = encoder.finish();
    let start = Instant::now();
    let submission = queue.submit([command]);
    match timestamps {
        Some(t) => {
            let bytes = scheduler::readback::map_read(device, &t.readback, submission, TIMEOUT)?;
            let wall = start.elapsed();
            let stamps: &[u64] = bytemuck::cast_slice(&bytes);
            Ok((timestamp_delta(stamps[0], stamps[1], t.period_ns), wall))
        }
        None => {
            scheduler::readback::wait(device, submission, TIMEOUT)?;
            let wall = start.elapsed();
            Ok((wall, wall))
        }
    }
}

/// A flat pipeline with its `out` buffer, ready to run repeatedly.
#[derive(Debug)]
pub struct FlatKernel {
    device: wgpu::Device,
    queue: wgpu::Queue,
    workload: Workload,
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    out: wgpu::Buffer,
    timestamps: Option<Timestamps>,
}

/// The complete WGSL module of the flat kernel for `workload`.
pub fn flat_wgsl(workload: &Workload) -> String {
    format!("{}{HASH_WGSL}{FLAT_WGSL}", workload.wgsl_constants())
}

impl FlatKernel {
    /// Creates the pipeline and the `out` buffer (not timed).
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        workload: Workload,
    ) -> Result<Self, BenchError> {
        // The very same runtime checks as the megakernel, so that both run the
        // same machine code for `bench_work`; its only loop is bounded by a
        // constant.
        let BoundKernel {
            pipeline,
            out,
            bind_group,
        } = BoundKernel::new(
            device,
            "flat kernel",
            flat_wgsl(&workload),
            workload.items(),
        )?;
        let timestamps = Timestamps::new(device, queue);
        Ok(Self {
            device: device.clone(),
            queue: queue.clone(),
            workload,
            pipeline,
            bind_group,
            out,
            timestamps,
        })
    }

    /// How [`FlatKernel::run`] times a run.
    pub fn time_source(&self) -> TimeSource {
        if self.timestamps.is_some() {
            TimeSource::GpuTimestamps
        } else {
            TimeSource::WallClock
        }
    }

    /// The `out` buffer.
    pub fn out(&self) -> &wgpu::Buffer {
        &self.out
    }

    /// Runs the dispatch once and returns its time (see [`Self::time_source`])
    /// and the host wall time from submission to completion.
    pub fn run(&self) -> Result<(Duration, Duration), BenchError> {
        dispatch_timed(
            &self.device,
            &self.queue,
            &self.pipeline,
            &self.bind_group,
            [self.workload.items().div_ceil(FLAT_WORKGROUP_SIZE), 1, 1],
            self.timestamps.as_ref(),
        )
    }

    /// Fills `out` with the sentinel, runs once and checks `out` against `expected`.
    pub fn run_verified(
        &self,
        expected: &[u32],
        variant: &str,
    ) -> Result<(Duration, Duration), BenchError> {
        verify::fill_sentinel(&self.queue, &self.out);
        let time = self.run()?;
        verify::check_out(&self.device, &self.queue, &self.out, expected, variant)?;
        Ok(time)
    }
}
