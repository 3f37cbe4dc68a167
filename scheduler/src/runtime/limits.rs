//! The device's limits, checked before anything is dispatched: a run that
//! would exceed one fails with [`RunError::ExceedsDeviceLimit`] naming the
//! limit, instead of a wgpu validation error in the middle of the run (or an
//! indirect dispatch the driver skips silently).

use crate::codegen::bindings::{self, Kernels};
use crate::plan::Plan;
use crate::{ResourceKind, RunError};

/// Fails when the device cannot run `plan` with `workgroups` persistent
/// workgroups: the module was compiled for limits (`CompileOptions::limits`)
/// that may exceed the device's.
pub(crate) fn check_plan(
    plan: &Plan,
    limits: &wgpu::Limits,
    workgroups: u32,
) -> Result<(), RunError> {
    let exceeds = |what: String, needed: u64, limit: u32, limit_name: &'static str| {
        (needed > u64::from(limit)).then(|| RunError::ExceedsDeviceLimit {
            what,
            needed,
            limit: u64::from(limit),
            limit_name,
        })
    };
    let checks = [
        // Megakernel dispatches launch `workgroups` in x; round dispatches
        // are clamped to the same number on the GPU.
        exceeds(
            "the persistent workgroups of one dispatch".into(),
            u64::from(workgroups),
            limits.max_compute_workgroups_per_dimension,
            "max_compute_workgroups_per_dimension",
        ),
        exceeds(
            "the workgroup size compiled for".into(),
            u64::from(plan.workgroup_size),
            limits.max_compute_invocations_per_workgroup,
            "max_compute_invocations_per_workgroup",
        ),
        exceeds(
            "the workgroup size compiled for".into(),
            u64::from(plan.workgroup_size),
            limits.max_compute_workgroup_size_x,
            "max_compute_workgroup_size_x",
        ),
        // Group 0 is the scheduler's, group 1 the graph's resources.
        exceeds(
            "bind groups".into(),
            if plan.resources.is_empty() { 1 } else { 2 },
            limits.max_bind_groups,
            "max_bind_groups",
        ),
    ];
    if let Some(error) = checks.into_iter().flatten().next() {
        return Err(error);
    }
    for kernels in Kernels::ALL {
        let count = bindings::buffers(kernels, &plan.resources);
        let own = bindings::scheduler_buffers(kernels);
        let what = |kind: &str, n: u32, own: u32| {
            format!("the {n} {kind} buffers of one stage ({own} of them the scheduler's)")
        };
        let checks = [
            exceeds(
                what("storage", count.storage, own.storage),
                u64::from(count.storage),
                limits.max_storage_buffers_per_shader_stage,
                "max_storage_buffers_per_shader_stage",
            ),
            exceeds(
                what("uniform", count.uniform, own.uniform),
                u64::from(count.uniform),
                limits.max_uniform_buffers_per_shader_stage,
                "max_uniform_buffers_per_shader_stage",
            ),
        ];
        if let Some(error) = checks.into_iter().flatten().next() {
            return Err(error);
        }
    }
    Ok(())
}

/// Fails when a buffer range bound to resource `name` exceeds the device's
/// binding size for its kind, or starts at an offset the device cannot bind.
pub(crate) fn check_binding(
    name: &str,
    kind: ResourceKind,
    offset: u64,
    bytes: u64,
    limits: &wgpu::Limits,
) -> Result<(), RunError> {
    let (size, size_name, alignment, alignment_name) = match kind {
        ResourceKind::Storage(_) => (
            limits.max_storage_buffer_binding_size,
            "max_storage_buffer_binding_size",
            limits.min_storage_buffer_offset_alignment,
            "min_storage_buffer_offset_alignment",
        ),
        ResourceKind::Uniform => (
            limits.max_uniform_buffer_binding_size,
            "max_uniform_buffer_binding_size",
            limits.min_uniform_buffer_offset_alignment,
            "min_uniform_buffer_offset_alignment",
        ),
    };
    let size = size.min(limits.max_buffer_size);
    if bytes > size {
        return Err(RunError::ExceedsDeviceLimit {
            what: format!("the {bytes}-byte binding of resource `{name}`"),
            needed: bytes,
            limit: size,
            limit_name: size_name,
        });
    }
    if !offset.is_multiple_of(u64::from(alignment.max(1))) {
        return Err(RunError::ExceedsDeviceLimit {
            what: format!(
                "the offset {offset} of resource `{name}`'s binding (a multiple of the limit is needed)"
            ),
            needed: offset,
            limit: u64::from(alignment),
            limit_name: alignment_name,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Access, CompileOptions, Graph, Procedure, Resource};

    #[crate::item]
    struct Node {
        id: u32,
    }

    fn plan(resources: usize) -> Plan {
        let mut graph = Graph::new("limits");
        for r in 0..resources {
            graph.resource(Resource::storage::<[u32]>(&format!("out{r}")));
        }
        graph.procedure(Procedure::of::<Node>("Run").initial(true).body(""));
        graph.compile(&CompileOptions::default()).unwrap().plan
    }

    fn limit_name(result: Result<(), RunError>) -> &'static str {
        match result {
            Err(RunError::ExceedsDeviceLimit { limit_name, .. }) => limit_name,
            other => panic!("expected ExceedsDeviceLimit, got {other:?}"),
        }
    }

    #[test]
    fn a_plan_beyond_the_device_is_refused_by_the_limit_it_exceeds() {
        let defaults = wgpu::Limits::default();
        check_plan(&plan(2), &defaults, 256).unwrap();
        assert_eq!(
            limit_name(check_plan(&plan(0), &defaults, 70_000)),
            "max_compute_workgroups_per_dimension"
        );
        // 3 storage buffers of the scheduler's and 2 of the graph's.
        let downlevel = wgpu::Limits {
            max_storage_buffers_per_shader_stage: 4,
            ..defaults.clone()
        };
        assert_eq!(
            limit_name(check_plan(&plan(2), &downlevel, 256)),
            "max_storage_buffers_per_shader_stage"
        );
        let small = wgpu::Limits {
            max_compute_invocations_per_workgroup: 128,
            ..defaults.clone()
        };
        assert_eq!(
            limit_name(check_plan(&plan(0), &small, 256)),
            "max_compute_invocations_per_workgroup"
        );
        let one_group = wgpu::Limits {
            max_bind_groups: 1,
            ..defaults
        };
        check_plan(&plan(0), &one_group, 256).unwrap();
        assert_eq!(
            limit_name(check_plan(&plan(1), &one_group, 256)),
            "max_bind_groups"
        );
    }

    #[test]
    fn bindings_beyond_the_device_are_refused() {
        let limits = wgpu::Limits::default();
        let storage = ResourceKind::Storage(Access::ReadWrite);
        check_binding("out", storage, 256, 1 << 20, &limits).unwrap();
        assert_eq!(
            limit_name(check_binding("out", storage, 0, 1 << 40, &limits)),
            "max_storage_buffer_binding_size"
        );
        assert_eq!(
            limit_name(check_binding("out", storage, 4, 16, &limits)),
            "min_storage_buffer_offset_alignment"
        );
        assert_eq!(
            limit_name(check_binding(
                "u",
                ResourceKind::Uniform,
                0,
                1 << 20,
                &limits
            )),
            "max_uniform_buffer_binding_size"
        );
    }
}
