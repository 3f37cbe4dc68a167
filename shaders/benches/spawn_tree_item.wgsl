struct SpawnItem { id: u32, depth: u32, parent: u32, pad0: u32, pad1: u32, pad2: u32, pad3: u32, pad4: u32 }
