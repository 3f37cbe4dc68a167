//! The binding table: every buffer the generated module binds, stated once.
//! The WGSL declarations and their comments, the bind group layouts, the
//! bind groups and the per-stage buffer count checked at compile time are all
//! read from [`SCHEDULER_BINDINGS`] (group 0) and from the graph's resources
//! (group 1, in declaration order).

use crate::codegen::uniform;
use crate::naming::{ENTRY_POINT, PREPARE_ENTRY_POINT, round_entry_point};
use crate::{Access, Resource, ResourceKind};

/// Bind group of the scheduler's own buffers.
pub(crate) const SCHEDULER_GROUP: u32 = 0;

/// Bind group of the graph's resources.
pub(crate) const RESOURCE_GROUP: u32 = 1;

// Pipeline layouts list the group layouts in this order.
const _: () = assert!(SCHEDULER_GROUP == 0 && RESOURCE_GROUP == 1);

/// How a buffer is bound: its WGSL address space and its wgpu binding type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BufferKind {
    Storage { read_only: bool },
    Uniform,
}

impl BufferKind {
    /// The address space between `var<` and `>`.
    pub(crate) fn address_space(self) -> &'static str {
        match self {
            Self::Storage { read_only: false } => "storage, read_write",
            Self::Storage { read_only: true } => "storage, read",
            Self::Uniform => "uniform",
        }
    }

    /// The layout entry for a buffer of this kind at `binding`.
    pub(crate) fn layout_entry(self, binding: u32) -> wgpu::BindGroupLayoutEntry {
        let ty = match self {
            Self::Storage { read_only } => wgpu::BufferBindingType::Storage { read_only },
            Self::Uniform => wgpu::BufferBindingType::Uniform,
        };
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }
    }
}

/// The kernels of a module, grouped by the group-0 layout they share.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kernels {
    /// The megakernel and the Rounds strategy's per-procedure kernels. Only
    /// these also bind the graph's resources (group 1).
    Procedures,
    /// The Rounds strategy's prepare kernel. It has a layout of its own
    /// because a buffer cannot be written as storage and read as indirect
    /// arguments in one dispatch.
    Prepare,
}

impl Kernels {
    pub(crate) const ALL: [Self; 2] = [Self::Procedures, Self::Prepare];

    /// Whether these kernels bind the graph's resources.
    pub(crate) fn bind_resources(self) -> bool {
        self == Self::Procedures
    }

    /// The entry points, as the generated comments name them.
    fn entry_points(self) -> String {
        match self {
            Self::Procedures => format!("{ENTRY_POINT} and {}", round_entry_point("<procedure>")),
            Self::Prepare => PREPARE_ENTRY_POINT.to_owned(),
        }
    }
}

/// The scheduler's own buffers. The discriminant is the binding in group 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SchedulerBuffer {
    QueueWords = 0,
    Control = 1,
    Staging = 2,
    Config = 3,
    Dispatch = 4,
}

/// What a scheduler buffer holds, which decides its WGSL type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Contents {
    /// Queue slots: plain `vec4<u32>` packets when the coherent memory
    /// decoration is compiled for, atomic words otherwise (relaxed atomics are
    /// always coherent).
    Payload,
    AtomicWords,
    Packets,
    /// The rows of [`uniform`], one per queue and one for the run.
    ConfigRows,
    Words,
}

/// One group-0 binding.
#[derive(Debug)]
pub(crate) struct SchedulerBinding {
    pub buffer: SchedulerBuffer,
    pub name: &'static str,
    pub kind: BufferKind,
    contents: Contents,
    /// The kernels whose layouts include it.
    pub kernels: &'static [Kernels],
    /// The comment in the module, before the generated parts (the payload
    /// note, the configuration rows, the kernels that bind it).
    doc: &'static str,
}

impl SchedulerBinding {
    pub(crate) fn binding(&self) -> u32 {
        self.buffer as u32
    }

    pub(crate) fn bound_to(&self, kernels: Kernels) -> bool {
        self.kernels.contains(&kernels)
    }
}

const READ_WRITE: BufferKind = BufferKind::Storage { read_only: false };

/// Group 0, in binding order.
pub(crate) const SCHEDULER_BINDINGS: [SchedulerBinding; 5] = [
    SchedulerBinding {
        buffer: SchedulerBuffer::QueueWords,
        name: "sched_queue_words",
        kind: READ_WRITE,
        contents: Contents::Payload,
        kernels: &[Kernels::Procedures],
        doc: "Item slots of every queue",
    },
    SchedulerBinding {
        buffer: SchedulerBuffer::Control,
        name: "sched_control",
        kind: READ_WRITE,
        contents: Contents::AtomicWords,
        kernels: &[Kernels::Procedures, Kernels::Prepare],
        doc: "Counters: outstanding work and per-queue statistics, then the range markers.",
    },
    SchedulerBinding {
        buffer: SchedulerBuffer::Staging,
        name: "sched_staging",
        kind: READ_WRITE,
        contents: Contents::Packets,
        kernels: &[Kernels::Procedures],
        doc: "Per-workgroup staging of enqueued items, copied into queue slots at the flush.",
    },
    SchedulerBinding {
        buffer: SchedulerBuffer::Config,
        name: "sched_config",
        kind: BufferKind::Uniform,
        contents: Contents::ConfigRows,
        kernels: &[Kernels::Procedures, Kernels::Prepare],
        doc: "",
    },
    SchedulerBinding {
        buffer: SchedulerBuffer::Dispatch,
        name: "sched_dispatch",
        kind: READ_WRITE,
        contents: Contents::Words,
        kernels: &[Kernels::Prepare],
        doc: "Rounds strategy: indirect dispatch sizes (x, y, z) per queue, written by sched_prepare_round.",
    },
];

// Listed in binding order, one buffer per binding, so the module declares
// them in that order and the table can be indexed by the buffer.
const _: () = {
    let mut i = 0;
    while i < SCHEDULER_BINDINGS.len() {
        assert!(SCHEDULER_BINDINGS[i].buffer as usize == i);
        i += 1;
    }
};

/// How a graph resource is bound.
pub(crate) fn resource_kind(resource: &Resource) -> BufferKind {
    match resource.kind() {
        ResourceKind::Storage(access) => BufferKind::Storage {
            read_only: access == Access::Read,
        },
        ResourceKind::Uniform => BufferKind::Uniform,
    }
}

/// The graph's resources with their bindings in group 1.
pub(crate) fn resource_bindings(
    resources: &[Resource],
) -> impl Iterator<Item = (u32, &Resource)> + '_ {
    (0u32..).zip(resources)
}

/// What the module is compiled for, as far as the declarations depend on it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shape {
    pub queues: usize,
    pub coherent: bool,
}

/// One binding as the module declares it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Declaration {
    pub group: u32,
    pub binding: u32,
    /// Attributes besides `@group` and `@binding` (`@coherent`).
    pub decoration: Option<&'static str>,
    pub kind: BufferKind,
    pub name: String,
    pub ty: String,
    pub doc: String,
}

impl Declaration {
    /// `@group(g) @binding(b)`, after any decoration.
    pub(crate) fn attributes(&self) -> String {
        let place = format!("@group({}) @binding({})", self.group, self.binding);
        match self.decoration {
            Some(decoration) => format!("{decoration} {place}"),
            None => place,
        }
    }
}

impl SchedulerBinding {
    /// The declaration of this binding in a module of `shape`.
    pub(crate) fn declaration(&self, shape: Shape) -> Declaration {
        let (decoration, ty, note) = match self.contents {
            Contents::Payload if shape.coherent => (
                Some("@coherent"),
                "array<vec4<u32>>".to_owned(),
                " (coherent: plain accesses are seen across workgroups after the fences).",
            ),
            Contents::Payload => (
                None,
                "array<atomic<u32>>".to_owned(),
                " (atomic words: no coherent memory decoration compiled for).",
            ),
            Contents::AtomicWords => (None, "array<atomic<u32>>".to_owned(), ""),
            Contents::Packets => (None, "array<vec4<u32>>".to_owned(), ""),
            Contents::ConfigRows => (
                None,
                format!("array<vec4<u32>, {}>", uniform::rows(shape.queues)),
                "",
            ),
            Contents::Words => (None, "array<u32>".to_owned(), ""),
        };
        let mut doc = format!("{}{note}", self.doc);
        if self.contents == Contents::ConfigRows {
            doc.push_str(&uniform::describe());
        }
        // Say who binds it when not every kernel does: binding it elsewhere
        // fails at pipeline creation.
        if self.kernels.len() < Kernels::ALL.len() {
            let names: Vec<String> = self.kernels.iter().map(|k| k.entry_points()).collect();
            doc.push_str(&format!(" Bound only to {}.", names.join(" and ")));
        }
        Declaration {
            group: SCHEDULER_GROUP,
            binding: self.binding(),
            decoration,
            kind: self.kind,
            name: self.name.to_owned(),
            ty,
            doc,
        }
    }
}

/// Every binding of a module of `shape` over `resources`: group 0, then group 1.
pub(crate) fn declarations(shape: Shape, resources: &[Resource]) -> Vec<Declaration> {
    let scheduler = SCHEDULER_BINDINGS.iter().map(|b| b.declaration(shape));
    let graph = resource_bindings(resources).map(|(binding, resource)| {
        let (name, ty) = (resource.name(), resource.wgsl_type());
        Declaration {
            group: RESOURCE_GROUP,
            binding,
            decoration: None,
            kind: resource_kind(resource),
            name: name.to_owned(),
            ty: ty.to_owned(),
            doc: "User resource.".to_owned(),
        }
    });
    scheduler.chain(graph).collect()
}

/// Storage and uniform buffers one stage of `kernels` binds: the scheduler's
/// and, for the procedure kernels, the graph's.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct BufferCount {
    pub storage: u32,
    pub uniform: u32,
}

impl BufferCount {
    fn add(&mut self, kind: BufferKind) {
        match kind {
            BufferKind::Storage { .. } => self.storage += 1,
            BufferKind::Uniform => self.uniform += 1,
        }
    }
}

/// The scheduler's own buffers bound to `kernels`.
pub(crate) fn scheduler_buffers(kernels: Kernels) -> BufferCount {
    let mut count = BufferCount::default();
    for binding in SCHEDULER_BINDINGS.iter().filter(|b| b.bound_to(kernels)) {
        count.add(binding.kind);
    }
    count
}

/// Every buffer bound to `kernels`, the graph's `resources` included.
pub(crate) fn buffers(kernels: Kernels, resources: &[Resource]) -> BufferCount {
    let mut count = scheduler_buffers(kernels);
    if kernels.bind_resources() {
        for resource in resources {
            count.add(resource_kind(resource));
        }
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bindings_are_distinct_and_every_kernel_binds_the_config() {
        for kernels in Kernels::ALL {
            assert!(SCHEDULER_BINDINGS[SchedulerBuffer::Config as usize].bound_to(kernels));
        }
        let shape = Shape {
            queues: 2,
            coherent: false,
        };
        let resources = [Resource::storage::<[u32]>("out")];
        let all = declarations(shape, &resources);
        let mut places: Vec<(u32, u32)> = all.iter().map(|d| (d.group, d.binding)).collect();
        places.sort();
        places.dedup();
        assert_eq!(places.len(), SCHEDULER_BINDINGS.len() + resources.len());
        assert_eq!(all.last().unwrap().attributes(), "@group(1) @binding(0)");
        assert_eq!(
            buffers(Kernels::Procedures, &resources),
            BufferCount {
                storage: 4,
                uniform: 1
            }
        );
        assert_eq!(
            buffers(Kernels::Prepare, &resources),
            BufferCount {
                storage: 2,
                uniform: 1
            }
        );
    }
}
