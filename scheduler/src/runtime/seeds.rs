//! Initial items given by the host.

use crate::{Item, ProcedureId, Untyped};

/// Initial items for one run, per procedure.
#[derive(Clone, Debug, Default)]
pub struct Seeds {
    pub(crate) entries: Vec<SeedEntry>,
}

#[derive(Clone, Debug)]
pub(crate) struct SeedEntry {
    pub procedure: String,
    pub bytes: Vec<u8>,
    pub count: usize,
    pub item_size: usize,
}

impl Seeds {
    /// No seeds.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds initial items for `procedure` (which must accept initial items).
    /// The items must be of the procedure's item type: anything else does
    /// not compile.
    pub fn add<T: Item>(mut self, procedure: &ProcedureId<T>, items: &[T]) -> Self {
        self.push(procedure, items);
        self
    }

    /// Adds initial items for `procedure` in place.
    pub fn push<T: Item>(&mut self, procedure: &ProcedureId<T>, items: &[T]) -> &mut Self {
        self.push_bytes(procedure.name(), items)
    }

    /// Adds initial items for an [`Untyped`] procedure (one declared with an
    /// explicit [`ItemType`](crate::ItemType)). Only their size is checked,
    /// when the run starts.
    pub fn add_untyped<T: bytemuck::Pod>(
        mut self,
        procedure: &ProcedureId<Untyped>,
        items: &[T],
    ) -> Self {
        self.push_untyped(procedure, items);
        self
    }

    /// Adds initial items for an [`Untyped`] procedure in place.
    pub fn push_untyped<T: bytemuck::Pod>(
        &mut self,
        procedure: &ProcedureId<Untyped>,
        items: &[T],
    ) -> &mut Self {
        self.push_bytes(procedure.name(), items)
    }

    fn push_bytes<T: bytemuck::Pod>(&mut self, procedure: &str, items: &[T]) -> &mut Self {
        self.entries.push(SeedEntry {
            procedure: procedure.to_owned(),
            bytes: bytemuck::cast_slice(items).to_vec(),
            count: items.len(),
            item_size: std::mem::size_of::<T>(),
        });
        self
    }

    /// Total number of seeded items.
    pub fn len(&self) -> usize {
        self.entries.iter().map(|e| e.count).sum()
    }

    /// Whether no item is seeded.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}
