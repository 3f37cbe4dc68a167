//! The extra buffers a graph's bodies and library use: declared by WGSL type
//! or, typed, by a Rust type whose WGSL twin the crate derives, with the
//! layout facts the executor needs to create, check and read them.

use crate::{WgslStructs, WgslType};

/// Access mode of a storage buffer resource.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// `var<storage, read>`
    Read,
    /// `var<storage, read_write>`
    ReadWrite,
}

/// How a resource is bound.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ResourceKind {
    /// `var<storage, access>`.
    Storage(Access),
    /// `var<uniform>`.
    Uniform,
}

/// The host-side shape of a typed resource: what the executor needs to
/// create it, check a bound buffer's size and read it back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BufferShape {
    /// Bytes of one element: the array stride of `array<T>`, or the size of
    /// a single `T`.
    pub element_bytes: u64,
    /// Whether the resource is a runtime-sized array (`array<T>`) rather
    /// than a single value.
    pub runtime_array: bool,
    /// The fewest elements a bound buffer must hold (1 for a single value).
    pub min_elements: u64,
}

impl BufferShape {
    /// The fewest bytes a bound buffer must hold.
    pub fn min_bytes(&self) -> u64 {
        self.element_bytes.saturating_mul(self.min_elements.max(1))
    }
}

/// A Rust type a buffer resource holds: a slice `[T]` (WGSL `array<T>`) or a
/// single `T`, for any `T` with a [`WgslType`] twin whose WGSL size equals
/// its Rust size.
pub trait BufferContents {
    /// The element type: `T` for both `[T]` and `T`.
    type Element: bytemuck::Pod + WgslType;
    /// Whether this is a runtime-sized array.
    const RUNTIME_ARRAY: bool;

    /// The WGSL type of the variable: `array<T>` or `T`.
    fn wgsl_type() -> String;
}

/// Checked at compile time for every element type used: the bytes the host
/// writes and reads must be the bytes WGSL addresses.
const fn element_bytes<T: WgslType>() -> u64 {
    let stride = crate::wgsl_layout::round_up(T::WGSL_SIZE, T::WGSL_ALIGN);
    assert!(
        std::mem::size_of::<T>() == stride,
        "the Rust size of a buffer element differs from its WGSL array stride"
    );
    stride as u64
}

impl<T: bytemuck::Pod + WgslType> BufferContents for [T] {
    type Element = T;
    const RUNTIME_ARRAY: bool = true;

    fn wgsl_type() -> String {
        format!("array<{}>", T::wgsl_type())
    }
}

impl<T: bytemuck::Pod + WgslType> BufferContents for T {
    type Element = T;
    const RUNTIME_ARRAY: bool = false;

    fn wgsl_type() -> String {
        T::wgsl_type()
    }
}

/// A 32-bit atomic as a buffer element: `Resource::storage::<[Atomic<u32>]>`
/// declares `array<atomic<u32>>`, which bodies update with `atomicAdd` and
/// the host reads as `u32` ([`Executor::read::<u32>`](crate::Executor::read)).
#[repr(transparent)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Atomic<T>(pub T);

impl WgslType for Atomic<u32> {
    const WGSL_ALIGN: usize = 4;
    const WGSL_SIZE: usize = 4;

    fn wgsl_type() -> String {
        "atomic<u32>".to_owned()
    }
}

impl WgslType for Atomic<i32> {
    const WGSL_ALIGN: usize = 4;
    const WGSL_SIZE: usize = 4;

    fn wgsl_type() -> String {
        "atomic<i32>".to_owned()
    }
}

/// An extra resource that bodies and the library use, bound in group 1 in
/// declaration order.
///
/// Declare it typed, and the crate writes its WGSL type (and the structs it
/// needs), creates, clears and reads the buffer
/// ([`Executor::create_buffer`](crate::Executor::create_buffer),
/// [`Executor::read`](crate::Executor::read)) and checks a bound buffer's
/// size before each run:
///
/// ```
/// use scheduler::{Atomic, Resource};
///
/// #[scheduler::item]
/// struct Params { scale: f32, count: u32 }
///
/// let counts = Resource::storage::<[Atomic<u32>]>("counts").min_len(64);
/// let params = Resource::uniform::<Params>("params");
/// assert_eq!(counts.wgsl_type(), "array<atomic<u32>>");
/// assert_eq!(params.wgsl_type(), "Params");
/// ```
///
/// A resource of a type only WGSL can state (a struct with atomics, say)
/// is declared by its WGSL type with [`Resource::storage_wgsl`] and friends,
/// and bound with a [`Binding`](crate::Binding) to your own buffer.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Resource {
    pub(crate) name: String,
    pub(crate) wgsl_type: String,
    pub(crate) kind: ResourceKind,
    /// Struct declarations the type needs, dependencies first.
    pub(crate) structs: Vec<(String, String)>,
    /// The host-side shape, for typed resources.
    pub(crate) shape: Option<BufferShape>,
}

impl Resource {
    fn typed<C: BufferContents + ?Sized>(name: impl Into<String>, kind: ResourceKind) -> Self {
        let mut structs = WgslStructs::default();
        C::Element::wgsl_structs(&mut structs);
        Self {
            name: name.into(),
            wgsl_type: C::wgsl_type(),
            kind,
            structs: structs
                .into_entries()
                .into_iter()
                .map(|(name, source)| (name.to_owned(), source))
                .collect(),
            shape: Some(BufferShape {
                element_bytes: const { element_bytes::<C::Element>() },
                runtime_array: C::RUNTIME_ARRAY,
                min_elements: 1,
            }),
        }
    }

    fn untyped(name: impl Into<String>, wgsl_type: impl Into<String>, kind: ResourceKind) -> Self {
        Self {
            name: name.into(),
            wgsl_type: wgsl_type.into(),
            kind,
            structs: Vec::new(),
            shape: None,
        }
    }

    /// A read-write storage buffer of `C`: `[T]` for `array<T>`, or `T`.
    pub fn storage<C: BufferContents + ?Sized>(name: impl Into<String>) -> Self {
        Self::typed::<C>(name, ResourceKind::Storage(Access::ReadWrite))
    }

    /// A read-only storage buffer of `C`: `[T]` for `array<T>`, or `T`.
    pub fn storage_read<C: BufferContents + ?Sized>(name: impl Into<String>) -> Self {
        Self::typed::<C>(name, ResourceKind::Storage(Access::Read))
    }

    /// A uniform buffer holding one `T` (a struct deriving
    /// [`Item`](crate::Item), typically). WGSL's uniform layout rules are
    /// stricter than storage's (16-byte array strides); naga checks them
    /// when the graph compiles.
    pub fn uniform<T: bytemuck::Pod + WgslType>(name: impl Into<String>) -> Self {
        Self::typed::<T>(name, ResourceKind::Uniform)
    }

    /// A read-write storage buffer of a WGSL type the library declares, e.g.
    /// `array<atomic<u32>>` or a struct with atomics.
    pub fn storage_wgsl(name: impl Into<String>, wgsl_type: impl Into<String>) -> Self {
        Self::untyped(name, wgsl_type, ResourceKind::Storage(Access::ReadWrite))
    }

    /// A read-only storage buffer of a WGSL type the library declares.
    pub fn storage_read_wgsl(name: impl Into<String>, wgsl_type: impl Into<String>) -> Self {
        Self::untyped(name, wgsl_type, ResourceKind::Storage(Access::Read))
    }

    /// A uniform buffer of a WGSL type the library declares.
    pub fn uniform_wgsl(name: impl Into<String>, wgsl_type: impl Into<String>) -> Self {
        Self::untyped(name, wgsl_type, ResourceKind::Uniform)
    }

    /// The fewest elements a bound buffer must hold, checked before every
    /// run ([`RunError::BufferTooSmall`](crate::RunError::BufferTooSmall))
    /// and used by [`Executor::create_buffer`](crate::Executor::create_buffer)
    /// as the default length. Only typed runtime arrays have a length; on
    /// other resources this does nothing.
    pub fn min_len(mut self, elements: u64) -> Self {
        if let Some(shape) = self.shape.as_mut().filter(|s| s.runtime_array) {
            shape.min_elements = elements.max(1);
        }
        self
    }

    /// The WGSL variable name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The WGSL type of the variable.
    pub fn wgsl_type(&self) -> &str {
        &self.wgsl_type
    }

    /// How the resource is bound.
    pub fn kind(&self) -> ResourceKind {
        self.kind
    }

    /// The host-side shape of a typed resource; `None` for one declared by
    /// its WGSL type.
    pub fn shape(&self) -> Option<BufferShape> {
        self.shape
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[scheduler::item]
    struct Pair {
        a: u32,
        b: f32,
    }

    #[test]
    fn typed_resources_derive_their_wgsl_and_shape() {
        let counts = Resource::storage::<[Atomic<u32>]>("counts").min_len(10);
        assert_eq!(counts.wgsl_type(), "array<atomic<u32>>");
        assert_eq!(
            counts.shape(),
            Some(BufferShape {
                element_bytes: 4,
                runtime_array: true,
                min_elements: 10
            })
        );
        assert_eq!(counts.shape().unwrap().min_bytes(), 40);

        let pairs = Resource::storage_read::<[Pair]>("pairs");
        assert_eq!(pairs.wgsl_type(), "array<Pair>");
        assert_eq!(pairs.kind(), ResourceKind::Storage(Access::Read));
        assert_eq!(pairs.structs.len(), 1);
        assert_eq!(pairs.structs[0].0, "Pair");

        let uniform = Resource::uniform::<Pair>("params").min_len(5);
        assert_eq!(uniform.kind(), ResourceKind::Uniform);
        // A single value has no length to raise.
        assert_eq!(uniform.shape().unwrap().min_elements, 1);
        assert_eq!(uniform.shape().unwrap().min_bytes(), 8);

        let glam = Resource::storage::<[glam::Vec4]>("points");
        assert_eq!(glam.wgsl_type(), "array<vec4<f32>>");
        assert_eq!(glam.shape().unwrap().element_bytes, 16);

        let untyped = Resource::storage_wgsl("log", "array<atomic<u32>>");
        assert_eq!(untyped.shape(), None);
    }
}
