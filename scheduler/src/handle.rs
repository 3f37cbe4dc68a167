//! Typed procedure handles: what [`Graph::procedure`](crate::Graph::procedure)
//! returns, and what connections, seeds and report look-ups take, so that a
//! procedure is named by a string once and its item type is checked by rustc.

use std::fmt;
use std::hash::{Hash, Hasher};
use std::marker::PhantomData;
use std::sync::Arc;

/// The item type parameter of a procedure declared with an explicit
/// [`ItemType`](crate::ItemType) (for example from
/// [`item_type!`](crate::item_type)): its seeds are checked by size at run
/// time only, through [`Seeds::add_untyped`](crate::Seeds::add_untyped).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Untyped {}

/// A procedure of a graph whose items are `T`.
///
/// ```
/// use scheduler::{Graph, Procedure, Seeds};
///
/// #[scheduler::item]
/// struct Node { depth: u32, id: u32 }
///
/// let mut graph = Graph::new("tree");
/// let grow = graph.procedure(Procedure::of::<Node>("Grow").initial(true));
/// graph.connect_with_fan_out(&grow, &grow, 2);
/// let seeds = Seeds::new().add(&grow, &[Node { depth: 0, id: 1 }]);
/// assert_eq!(grow.name(), "Grow");
/// # assert_eq!(seeds.len(), 1);
/// ```
///
/// Seeding with items of another type does not compile:
///
/// ```compile_fail,E0308
/// # use scheduler::{Graph, Procedure, Seeds};
/// #[scheduler::item]
/// struct Hop { node: u32, level: u32 }
///
/// let mut graph = Graph::new("bfs");
/// let visit = graph.procedure(Procedure::of::<Hop>("Visit").initial(true));
/// // Same size as a `Hop`, but not a `Hop`: mismatched types.
/// let seeds = Seeds::new().add(&visit, &[[0u32, 0u32]]);
/// ```
///
/// Inside WGSL bodies a procedure is still named by its name
/// (`enqueue_Grow(...)`). A handle is cheap to clone.
pub struct ProcedureId<T> {
    name: Arc<str>,
    item: PhantomData<fn() -> T>,
}

impl ProcedureId<Untyped> {
    /// An untyped handle for the procedure called `name`, for code that knows
    /// a procedure only by its name. Prefer the handle that
    /// [`Graph::procedure`](crate::Graph::procedure) returns.
    pub fn named(name: impl Into<Arc<str>>) -> Self {
        Self::new(name.into())
    }
}

impl<T> ProcedureId<T> {
    pub(crate) fn new(name: Arc<str>) -> Self {
        Self {
            name,
            item: PhantomData,
        }
    }

    /// The procedure's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The same procedure as an untyped handle.
    pub fn untyped(&self) -> ProcedureId<Untyped> {
        ProcedureId::new(self.name.clone())
    }
}

// Written out rather than derived: derives would require `T: Clone` and so
// on, but `T` is only a marker.
impl<T> Clone for ProcedureId<T> {
    fn clone(&self) -> Self {
        Self::new(self.name.clone())
    }
}

impl<T> fmt::Debug for ProcedureId<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ProcedureId")
            .field("name", &self.name)
            .field("item", &std::any::type_name::<T>())
            .finish()
    }
}

impl<T> fmt::Display for ProcedureId<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name)
    }
}

impl<T> PartialEq for ProcedureId<T> {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
    }
}

impl<T> Eq for ProcedureId<T> {}

impl<T> Hash for ProcedureId<T> {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.name.hash(state);
    }
}
