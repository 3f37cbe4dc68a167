//! The result of compiling a graph and what it answers about itself.

use std::sync::Arc;

use crate::naming::ENTRY_POINT;
use crate::plan::{Plan, QueuePlan};
use crate::{Item, ProcedureId};

/// A compiled graph: the WGSL megakernel plus everything the runtime needs.
/// It holds no GPU objects; create an [`Executor`](crate::Executor) to run it.
#[derive(Clone, Debug)]
pub struct CompiledGraph {
    pub(crate) plan: Plan,
    pub(crate) wgsl: String,
    pub(crate) module: naga::Module,
    /// Workgroup memory, measured on `module`.
    pub(crate) workgroup_bytes: u32,
    pub(crate) specialization: Specialization,
}

/// What specialization ([`CompileOptions::specialize`](crate::CompileOptions::specialize))
/// removed from the generated module.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Specialization {
    /// `if` statements whose constant condition chose one branch.
    pub folded_branches: usize,
    /// Functions no entry point reaches any more, dropped, in module order.
    pub dropped_functions: Vec<String>,
}

impl CompiledGraph {
    /// The generated WGSL (deterministic for a given graph and options).
    pub fn wgsl(&self) -> &str {
        &self.wgsl
    }

    /// What specialization removed (nothing when it was off).
    pub fn specialization(&self) -> &Specialization {
        &self.specialization
    }

    /// Lines and functions (entry points included) of the module: what
    /// the driver compiles.
    pub fn module_size(&self) -> (usize, usize) {
        (
            self.wgsl.lines().count(),
            self.module.functions.len() + self.module.entry_points.len(),
        )
    }

    /// The validated naga module.
    pub fn naga_module(&self) -> &naga::Module {
        &self.module
    }

    /// The name of the compute entry point.
    pub fn entry_point(&self) -> &'static str {
        ENTRY_POINT
    }

    /// Per-procedure queue plans, in declaration order.
    pub fn queues(&self) -> &[QueuePlan] {
        &self.plan.queues
    }

    /// The workgroup size compiled for.
    pub fn workgroup_size(&self) -> u32 {
        self.plan.workgroup_size
    }

    /// Bytes of workgroup memory, measured on the module: the scheduler's
    /// variables, the shared scratch and every `var<workgroup>` of the
    /// library, each rounded up to 16 bytes as WebGPU counts them. Compiling
    /// checks it against `max_compute_workgroup_storage_size`.
    pub fn workgroup_memory_bytes(&self) -> u32 {
        self.workgroup_bytes
    }

    /// Features the module was compiled for (the device must have them).
    pub fn features(&self) -> wgpu::Features {
        self.plan.features
    }
}

impl CompiledGraph {
    /// The handle of the procedure called `name`, if its items are `T` (the
    /// same WGSL struct name and size): for code that gets a compiled graph
    /// without the handles its graph returned.
    pub fn procedure_id<T: Item>(&self, name: &str) -> Option<ProcedureId<T>> {
        self.queues()
            .iter()
            .find(|q| {
                q.name == name
                    && q.item == T::WGSL_NAME
                    && q.item_words as usize * 4 == std::mem::size_of::<T>()
            })
            .map(|q| ProcedureId::new(Arc::from(q.name.as_str())))
    }
}
