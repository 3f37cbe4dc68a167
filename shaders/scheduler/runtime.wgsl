// ---- scheduler runtime (shaders/scheduler/runtime.wgsl) ----
// Queue protocol shared by every generated megakernel. The generated part of the
// module defines the SCHED_* constants, the bindings and the workgroup variables
// used here. docs/scheduler.md argues why the protocol is race-free and terminates.
//
// Each queue is a ring of `capacity` slots. A slot holds one item (item_words
// words) plus one sequence word. The sequence word is stored relative to the slot
// index s, so a zero-filled buffer is a valid empty queue:
//   seq == t - s        slot is free for the producer holding ticket t
//   seq == t - s + 1    slot holds the item of ticket t (published)
// Tickets are handed out by the `tail` counter (producers) and `head` counter
// (consumers); the slot of ticket t is t % capacity.

fn sched_ctrl(q: u32, field: u32) -> u32 {
    return SCHED_CTRL_QUEUE_BASE + q * SCHED_CTRL_QUEUE_STRIDE + field;
}

fn sched_capacity(q: u32) -> u32 {
    return sched_config[q].x;
}

fn sched_slot_word(q: u32, ticket: u32, word: u32) -> u32 {
    let slot = ticket % sched_capacity(q);
    return sched_config[q].y + slot * sched_item_words[q] + word;
}

fn sched_seq_word(q: u32, ticket: u32) -> u32 {
    return sched_config[q].z + ticket % sched_capacity(q);
}

fn sched_slot_base(ticket: u32, q: u32) -> u32 {
    return ticket - ticket % sched_capacity(q);
}

// Consumer side, thread 0 only: claim up to `max_items` tickets of queue q.
// Returns (first ticket, count); count 0 means the queue looked empty. The
// compare-exchange loop is lock-free; after a bounded number of lost races the
// workgroup simply tries the next queue.
fn sched_try_claim(q: u32, max_items: u32) -> vec2<u32> {
    for (var attempt = 0u; attempt < 16u; attempt += 1u) {
        let head = atomicLoad(&sched_control[sched_ctrl(q, SCHED_Q_HEAD)]);
        let tail = atomicLoad(&sched_control[sched_ctrl(q, SCHED_Q_TAIL)]);
        let available = tail - head;
        if (available == 0u || available > 0x80000000u) {
            return vec2<u32>(0u, 0u);
        }
        // Never more than the capacity: a batch then cannot hold both ticket
        // t and t - capacity (see docs/scheduler.md).
        let n = min(min(available, max_items), sched_capacity(q));
        let swap = atomicCompareExchangeWeak(&sched_control[sched_ctrl(q, SCHED_Q_HEAD)], head, head + n);
        if (swap.exchanged) {
            // `fill` counts reserved-but-unclaimed items; producers test it
            // against the capacity before they take tickets.
            atomicSub(&sched_control[sched_ctrl(q, SCHED_Q_FILL)], n);
            return vec2<u32>(head, n);
        }
    }
    return vec2<u32>(0u, 0u);
}

// Thread 0 only: choose the next batch. Returns (queue, first ticket, count, _),
// or SCHED_IDLE / SCHED_EXIT in .x.
fn sched_pick(workgroup: u32, iteration: u32) -> vec4<u32> {
    let start = sched_policy_start(workgroup, iteration);
    for (var i = 0u; i < SCHED_NUM_QUEUES; i += 1u) {
        let q = sched_queue_order[(start + i) % SCHED_NUM_QUEUES];
        let claim = sched_try_claim(q, sched_items_per_workgroup[q]);
        if (claim.y > 0u) {
            return vec4<u32>(q, claim.x, claim.y, 0u);
        }
    }
    // Outstanding work counts every item from the moment a producer reserved
    // its ticket until its own children are reserved and it has finished, so
    // zero means no item exists anywhere and none can be created any more.
    if (atomicLoad(&sched_control[SCHED_CTRL_PENDING]) == 0u) {
        return vec4<u32>(SCHED_EXIT, 0u, 0u, 0u);
    }
    return vec4<u32>(SCHED_IDLE, 0u, 0u, 0u);
}

// Consumer side, all threads: copy the `count` claimed items of queue q into
// this workgroup's inbox, releasing each slot as soon as its item is copied.
// Items are copied as they become published, so a slot is never held while
// waiting for a different item: the producer of a later ticket may be waiting
// for exactly this slot (docs/scheduler.md, "Progress").
fn sched_receive(lid: u32, q: u32, first: u32, count: u32) {
    let words = sched_item_words[q];
    var waiting = lid < count;
    if (lid == 0u) {
        atomicStore(&sched_wg_remaining, count);
    }
    loop {
        var ready = false;
        if (waiting) {
            let ticket = first + lid;
            ready = atomicLoad(&sched_queue_words[sched_seq_word(q, ticket)]) == sched_slot_base(ticket, q) + 1u;
        }
        // Acquire: payload loads come after the publication was observed.
        storageBarrier();
        if (ready) {
            let source = sched_slot_word(q, first + lid, 0u);
            let inbox = sched_wg_base + lid * words;
            for (var w = 0u; w < words; w += 1u) {
                sched_staging[inbox + w] = atomicLoad(&sched_queue_words[source + w]);
            }
        }
        // Release: the payload loads complete before the slot is handed back.
        storageBarrier();
        if (ready) {
            sched_release(q, first + lid);
            waiting = false;
            atomicSub(&sched_wg_remaining, 1u);
        }
        workgroupBarrier();
        if (lid == 0u) {
            sched_wg_remaining_snapshot = atomicLoad(&sched_wg_remaining);
        }
        if (workgroupUniformLoad(&sched_wg_remaining_snapshot) == 0u) {
            break;
        }
    }
}

// Consumer side: hand the slot of `ticket` to the producer of ticket + capacity.
fn sched_release(q: u32, ticket: u32) {
    let cap = sched_capacity(q);
    atomicStore(&sched_queue_words[sched_seq_word(q, ticket)], ticket - ticket % cap + cap);
}

// Producer side: spin until the consumer of ticket - capacity released the slot.
// The capacity test in sched_flush guarantees that ticket was already claimed by
// a running workgroup, which releases it without waiting on anything else
// (see docs/scheduler.md, "Progress").
fn sched_wait_free(q: u32, ticket: u32) {
    let want = ticket - ticket % sched_capacity(q);
    let word = sched_seq_word(q, ticket);
    loop {
        if (atomicLoad(&sched_queue_words[word]) == want) {
            break;
        }
    }
}

// Producer side, all threads: moves the items a workgroup staged for queue q into the queue. Called by
// every thread at the top level of the generated runner (uniform control flow).
// Publication order: payload words (atomic stores), a device-scope release
// fence (storageBarrier), then the sequence word.
fn sched_flush(lid: u32, q: u32, stage_offset: u32, stage_capacity: u32) {
    workgroupBarrier();
    storageBarrier();
    if (lid == 0u) {
        let staged = min(atomicLoad(&sched_wg_staged[q]), stage_capacity);
        var first = 0u;
        var accepted = 0u;
        if (staged > 0u) {
            let cap = sched_capacity(q);
            let old = atomicAdd(&sched_control[sched_ctrl(q, SCHED_Q_FILL)], staged);
            if (old < cap) {
                accepted = min(staged, cap - old);
            }
            if (accepted < staged) {
                // Overflow: record it, give the reservation back and never
                // count the dropped items as outstanding work.
                atomicSub(&sched_control[sched_ctrl(q, SCHED_Q_FILL)], staged - accepted);
                atomicAdd(&sched_control[sched_ctrl(q, SCHED_Q_DROPPED)], staged - accepted);
                atomicMax(&sched_control[sched_ctrl(q, SCHED_Q_NEEDED)], old + staged);
            }
            if (accepted > 0u) {
                atomicAdd(&sched_control[SCHED_CTRL_PENDING], accepted);
                first = atomicAdd(&sched_control[sched_ctrl(q, SCHED_Q_TAIL)], accepted);
                atomicMax(&sched_control[sched_ctrl(q, SCHED_Q_HIGH_WATER)], old + accepted);
                atomicAdd(&sched_control[sched_ctrl(q, SCHED_Q_ENQUEUED)], accepted);
            }
        }
        atomicStore(&sched_wg_staged[q], 0u);
        sched_wg_flush = vec2<u32>(first, accepted);
    }
    let flush = workgroupUniformLoad(&sched_wg_flush);
    if (flush.y == 0u) {
        return;
    }
    for (var k = lid; k < flush.y; k += SCHED_WORKGROUP_SIZE) {
        sched_wait_free(q, flush.x + k);
    }
    // Acquire: the consumers' reads of these slots happen before our writes.
    storageBarrier();
    let words = sched_item_words[q];
    let source = sched_wg_base + SCHED_INBOX_WORDS + stage_offset;
    for (var w = lid; w < flush.y * words; w += SCHED_WORKGROUP_SIZE) {
        atomicStore(&sched_queue_words[sched_slot_word(q, flush.x + w / words, w % words)], sched_staging[source + w]);
    }
    // Release: payload words are visible before any sequence word says so.
    storageBarrier();
    for (var k = lid; k < flush.y; k += SCHED_WORKGROUP_SIZE) {
        let ticket = flush.x + k;
        atomicStore(&sched_queue_words[sched_seq_word(q, ticket)], sched_slot_base(ticket, q) + 1u);
    }
}

// Staging: called from enqueue_<Target>. Returns the first staging word for the
// item, or 0xffffffff when the workgroup exceeded its staging room for q (the
// item is then counted as a fan-out overflow, never dropped silently).
fn sched_stage(q: u32, stage_offset: u32, stage_capacity: u32) -> u32 {
    let index = atomicAdd(&sched_wg_staged[q], 1u);
    if (index >= stage_capacity) {
        atomicAdd(&sched_control[sched_ctrl(q, SCHED_Q_FANOUT_OVERFLOW)], 1u);
        return 0xffffffffu;
    }
    return sched_wg_base + SCHED_INBOX_WORDS + stage_offset + index * sched_item_words[q];
}

// Scratch accessors: `slot` is the item's slot in the workgroup, `index` a word
// index below the procedure's declared scratch size (in 4-byte words).
fn scratch_load_u32(slot: u32, index: u32) -> u32 {
    return sched_wg_scratch[sched_scratch_word(slot, index)];
}
fn scratch_store_u32(slot: u32, index: u32, value: u32) {
    sched_wg_scratch[sched_scratch_word(slot, index)] = value;
}
fn scratch_load_f32(slot: u32, index: u32) -> f32 {
    return bitcast<f32>(scratch_load_u32(slot, index));
}
fn scratch_store_f32(slot: u32, index: u32, value: f32) {
    scratch_store_u32(slot, index, bitcast<u32>(value));
}
fn scratch_load_i32(slot: u32, index: u32) -> i32 {
    return bitcast<i32>(scratch_load_u32(slot, index));
}
fn scratch_store_i32(slot: u32, index: u32, value: i32) {
    scratch_store_u32(slot, index, bitcast<u32>(value));
}
fn sched_scratch_word(slot: u32, index: u32) -> u32 {
    // Clamp the index into the procedure's own region so a bad index can never
    // reach another item's scratch.
    return slot * sched_scratch_stride + min(index, max(sched_scratch_stride, 1u) - 1u);
}
