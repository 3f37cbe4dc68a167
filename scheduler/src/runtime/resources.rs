//! The graph's resources on the device: buffers the executor creates for
//! typed resources, their typed write, clear and read-back, and the bind
//! group of a run, with every bound buffer's size checked first.

use std::collections::BTreeMap;

use crate::codegen::bindings::resource_bindings;
use crate::runtime::readback::read_buffer;
use crate::{BufferShape, Executor, Resource, ResourceKind, RunError};

use super::executor::Binding;
use super::limits;

/// Buffers the executor owns, by resource name.
#[derive(Debug, Default)]
pub(crate) struct OwnedBuffers {
    buffers: BTreeMap<String, wgpu::Buffer>,
}

impl OwnedBuffers {
    fn get(&self, name: &str) -> Option<&wgpu::Buffer> {
        self.buffers.get(name)
    }
}

impl Executor {
    /// The declared resource `name` and its typed shape.
    fn typed_resource(&self, name: &str) -> Result<(&Resource, BufferShape), RunError> {
        let resource = self
            .compiled
            .plan
            .resources
            .iter()
            .find(|r| r.name() == name)
            .ok_or_else(|| RunError::Binding(format!("`{name}` is not a declared resource")))?;
        let shape = resource.shape().ok_or_else(|| {
            RunError::Binding(format!(
                "resource `{name}` is declared by its WGSL type (`{}`), so the executor cannot size or read it; declare it typed (`Resource::storage::<[T]>`) or bind your own buffer",
                resource.wgsl_type()
            ))
        })?;
        Ok((resource, shape))
    }

    /// Checks that `T` is the element type the resource declares, by size.
    fn check_element<T>(name: &str, shape: BufferShape) -> Result<(), RunError> {
        let bytes = std::mem::size_of::<T>() as u64;
        if bytes != shape.element_bytes {
            return Err(RunError::Binding(format!(
                "resource `{name}` has {} bytes per element, but `{}` has {bytes}",
                shape.element_bytes,
                std::any::type_name::<T>()
            )));
        }
        Ok(())
    }

    /// Creates the executor's own zeroed buffer for the typed resource
    /// `name`, holding `elements` elements (1 for a single value), and binds
    /// it in every later run that does not bind `name` itself. Replaces an
    /// earlier one. Fails with [`RunError::BufferTooSmall`] below the
    /// resource's [`min_len`](crate::Resource::min_len), and with
    /// [`RunError::TooLarge`] past the device's limits.
    pub fn create_buffer(&mut self, name: &str, elements: u64) -> Result<&wgpu::Buffer, RunError> {
        let (resource, shape) = self.typed_resource(name)?;
        if !shape.runtime_array && elements != 1 {
            return Err(RunError::Binding(format!(
                "resource `{name}` holds a single `{}`, not {elements} elements",
                resource.wgsl_type()
            )));
        }
        let bytes = shape.element_bytes.saturating_mul(elements);
        if bytes < shape.min_bytes() {
            return Err(RunError::BufferTooSmall {
                resource: name.to_owned(),
                bytes,
                needed: shape.min_bytes(),
            });
        }
        let limits = self.device.limits();
        let (usage, limit) = match resource.kind() {
            ResourceKind::Storage(_) => (
                wgpu::BufferUsages::STORAGE,
                limits.max_storage_buffer_binding_size,
            ),
            ResourceKind::Uniform => (
                wgpu::BufferUsages::UNIFORM,
                limits.max_uniform_buffer_binding_size,
            ),
        };
        let limit = limit.min(limits.max_buffer_size);
        if bytes > limit {
            return Err(RunError::TooLarge {
                what: "resource buffer",
                needed: bytes,
                limit,
            });
        }
        let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(name),
            size: bytes,
            usage: usage | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        self.owned.buffers.insert(name.to_owned(), buffer);
        Ok(&self.owned.buffers[name])
    }

    /// Writes `data` to the executor's buffer for `name`, creating it (or
    /// replacing it, when its length differs) with `data.len()` elements.
    /// `T` must have the declared element's size.
    pub fn write<T: bytemuck::Pod>(&mut self, name: &str, data: &[T]) -> Result<(), RunError> {
        let (_, shape) = self.typed_resource(name)?;
        Self::check_element::<T>(name, shape)?;
        let bytes = std::mem::size_of_val(data) as u64;
        if self.owned.get(name).is_none_or(|b| b.size() != bytes) {
            self.create_buffer(name, data.len() as u64)?;
        }
        self.queue
            .write_buffer(&self.owned.buffers[name], 0, bytemuck::cast_slice(data));
        Ok(())
    }

    /// Zeroes the executor's buffer for `name`.
    pub fn clear(&mut self, name: &str) -> Result<(), RunError> {
        let buffer = self.owned_buffer(name)?;
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("clear resource"),
            });
        encoder.clear_buffer(buffer, 0, None);
        self.queue.submit([encoder.finish()]);
        Ok(())
    }

    /// Reads the executor's buffer for `name` back as `T`s, waiting for the
    /// work submitted so far (within the executor's timeout). `T` must have
    /// the declared element's size: `u32` for `Atomic<u32>`, say.
    pub fn read<T: bytemuck::Pod>(&self, name: &str) -> Result<Vec<T>, RunError> {
        let (_, shape) = self.typed_resource(name)?;
        Self::check_element::<T>(name, shape)?;
        let bytes = read_buffer(
            &self.device,
            &self.queue,
            self.owned_buffer(name)?,
            self.timeout,
        )?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// The executor's own buffer for `name`, if it created one.
    pub fn buffer(&self, name: &str) -> Option<&wgpu::Buffer> {
        self.owned.get(name)
    }

    fn owned_buffer(&self, name: &str) -> Result<&wgpu::Buffer, RunError> {
        self.typed_resource(name)?;
        self.owned.get(name).ok_or_else(|| {
            RunError::Binding(format!(
                "the executor has no buffer for `{name}`: create it with `create_buffer` or `write`"
            ))
        })
    }

    /// The bind group of the graph's resources for one run: `bindings` first,
    /// then the executor's own buffers. Every resource must be bound, and
    /// every typed one by a buffer range of at least its minimum size.
    pub(super) fn resource_bind_group(
        &self,
        bindings: &[Binding<'_>],
    ) -> Result<Option<wgpu::BindGroup>, RunError> {
        let resources = &self.compiled.plan.resources;
        for b in bindings {
            if !resources.iter().any(|r| r.name() == b.name) {
                return Err(RunError::Binding(format!(
                    "`{}` is not a declared resource",
                    b.name
                )));
            }
        }
        let Some(layout) = &self.resource_layout else {
            return Ok(None);
        };
        let mut entries = Vec::with_capacity(resources.len());
        for (index, resource) in resource_bindings(resources) {
            let name = resource.name();
            let bound = match bindings.iter().find(|b| b.name == name) {
                Some(binding) => binding.resource.clone(),
                None => self
                    .owned
                    .get(name)
                    .ok_or_else(|| RunError::Binding(format!("resource `{name}` is not bound")))?
                    .as_entire_binding(),
            };
            if let wgpu::BindingResource::Buffer(range) = &bound {
                let bytes = range.size.map_or_else(
                    || range.buffer.size().saturating_sub(range.offset),
                    |size| size.get(),
                );
                limits::check_binding(
                    name,
                    resource.kind(),
                    range.offset,
                    bytes,
                    &self.device.limits(),
                )?;
                if let Some(shape) = resource.shape()
                    && bytes < shape.min_bytes()
                {
                    return Err(RunError::BufferTooSmall {
                        resource: name.to_owned(),
                        bytes,
                        needed: shape.min_bytes(),
                    });
                }
            }
            entries.push(wgpu::BindGroupEntry {
                binding: index,
                resource: bound,
            });
        }
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("graph resources"),
            layout,
            entries: &entries,
        });
        if let Some(error) = pollster::block_on(scope.pop()) {
            return Err(RunError::Binding(error.to_string()));
        }
        Ok(Some(group))
    }
}
