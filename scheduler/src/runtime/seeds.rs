//! Initial items given by the host.

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
    pub fn add<T: bytemuck::Pod>(mut self, procedure: &str, items: &[T]) -> Self {
        self.push(procedure, items);
        self
    }

    /// Adds initial items for `procedure` in place.
    pub fn push<T: bytemuck::Pod>(&mut self, procedure: &str, items: &[T]) -> &mut Self {
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
