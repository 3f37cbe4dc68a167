// ---- scheduler runtime (shaders/scheduler/runtime.wgsl) ----
// Queue protocol shared by every generated megakernel. The generated part of
// the module defines the SCHED_* constants, the bindings, the workgroup
// variables and sched_payload_load/store used here. docs/scheduler.md argues
// why the protocol is race-free and why it terminates.
//
// Each queue is a ring of `capacity` item slots (a power of two). Tickets come
// from four counters in the control buffer, all wrapping u32:
//   tail       next ticket a producer reserves
//   published  every ticket below it holds a complete item
//   head       next ticket a consumer claims (never beyond `published`)
//   released   every ticket below it has been copied out; its slot is free
// Producers and consumers move whole ranges: a producer reserves [b, b+n),
// writes the items, and leaves a marker "[b, b+n) is complete" at slot b.
// `published` then moves over every complete range that starts where it
// stands: whoever completes a range, or looks for work, moves it (helping), so
// nobody waits for the owner of an earlier range, however late its thread
// runs. Consumers claim only published items and release their ranges the
// same way. So no item is ever read half-written, and no per-item flag is
// needed. The only wait left is a producer's for free slots in a full ring.
//
// The Rounds strategy (one entry point per procedure, dispatched round after
// round) uses the same rings without markers: sched_prepare_round moves
// `head`, `released` and `published` between dispatches, and the dispatch
// boundary orders the writes. `sched_rounds` switches the markers off.

fn sched_ctrl(q: u32, field: u32) -> u32 {
    return SCHED_CTRL_QUEUE_BASE + q * SCHED_CTRL_QUEUE_STRIDE + field;
}

fn sched_capacity(q: u32) -> u32 {
    return sched_config[q].x + 1u;
}

fn sched_slot_word(q: u32, ticket: u32) -> u32 {
    return sched_config[q].y + (ticket & sched_config[q].x) * sched_slot_words[q];
}

// Control word of the marker for `ticket` of queue q: `markers` is 0 for
// published ranges and the capacity for released ones.
fn sched_marker(q: u32, markers: u32, ticket: u32) -> u32 {
    return sched_config[q].z + markers + (ticket & sched_config[q].x);
}

// Thread 0 only: records that the range [first, end) of queue q is complete
// (published, or released), then helps move the counter `field` over it.
fn sched_complete_range(q: u32, field: u32, markers: u32, first: u32, end: u32) {
    atomicStore(&sched_control[sched_marker(q, markers, first)], end);
    sched_advance(q, field, markers);
}

// Moves counter `field` of queue q over each complete range that starts where
// it stands. A marker left in the slot by an earlier lap lies behind the
// counter, so its length wraps beyond the capacity and is ignored. Bounded:
// whatever is left is picked up by the next helper.
fn sched_advance(q: u32, field: u32, markers: u32) {
    let index = sched_ctrl(q, field);
    let capacity = sched_capacity(q);
    for (var i = 0u; i < 64u; i += 1u) {
        let at = atomicLoad(&sched_control[index]);
        let end = atomicLoad(&sched_control[sched_marker(q, markers, at)]);
        let length = end - at;
        if (length == 0u || length > capacity) {
            return;
        }
        // Losing the race means another helper moved it: look again.
        _ = atomicCompareExchangeWeak(&sched_control[index], at, end);
    }
}

// Thread 0 only: waits until `released` of queue q reaches `goal` (wrapping
// compare), helping to move it. Consumers release without waiting on anyone,
// so this ends. llvmpipe (Mesa's software driver behind lavapipe) gives an
// invocation one budget of 65535 loop iterations for all its loops
// (docs/scheduler.md, "Loop limits"), so each iteration checks 64 times in
// straight-line code. Should the wait still run the budget out, the run is
// flagged and fails loudly.
fn sched_wait_released(q: u32, goal: u32) {
    let index = sched_ctrl(q, SCHED_Q_RELEASED);
    for (var round = 0u; round < 65535u; round += 1u) {
        sched_spins += 1u;
        if (sched_reached_64(index, goal)) {
            return;
        }
        sched_advance(q, SCHED_Q_RELEASED, sched_capacity(q));
    }
    atomicAdd(&sched_control[SCHED_CTRL_LOOPS_CUT], 1u);
}

fn sched_reached(index: u32, goal: u32) -> bool {
    return i32(atomicLoad(&sched_control[index]) - goal) >= 0;
}

// 64 checks of sched_reached, without a loop.
fn sched_reached_64(index: u32, goal: u32) -> bool {
    return sched_reached_8(index, goal) || sched_reached_8(index, goal) || sched_reached_8(index, goal)
        || sched_reached_8(index, goal) || sched_reached_8(index, goal) || sched_reached_8(index, goal)
        || sched_reached_8(index, goal) || sched_reached_8(index, goal);
}

// Eight checks of sched_reached, without a loop.
fn sched_reached_8(index: u32, goal: u32) -> bool {
    return sched_reached(index, goal) || sched_reached(index, goal) || sched_reached(index, goal)
        || sched_reached(index, goal) || sched_reached(index, goal) || sched_reached(index, goal)
        || sched_reached(index, goal) || sched_reached(index, goal);
}

// Consumer side, thread 0 only: claim up to `max_items` published tickets of
// queue q. Returns (first ticket, count); count 0 means nothing to take. The
// compare-exchange loop is lock-free; after a bounded number of lost races the
// workgroup simply tries the next queue.
fn sched_try_claim(q: u32, max_items: u32) -> vec2<u32> {
    for (var attempt = 0u; attempt < 16u; attempt += 1u) {
        let head = atomicLoad(&sched_control[sched_ctrl(q, SCHED_Q_HEAD)]);
        var published = atomicLoad(&sched_control[sched_ctrl(q, SCHED_Q_PUBLISHED)]);
        if (published == head) {
            // Help: a producer may have completed a range that nobody has
            // published yet (its own attempt raced with an earlier range's).
            sched_advance(q, SCHED_Q_PUBLISHED, 0u);
            published = atomicLoad(&sched_control[sched_ctrl(q, SCHED_Q_PUBLISHED)]);
        }
        let available = published - head;
        if (available == 0u || available > 0x80000000u) {
            return vec2<u32>(0u, 0u);
        }
        let n = min(available, max_items);
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

// All threads, once, after the persistent loop or a round's loop, with
// whether the loop ended by its own condition. llvmpipe's loop budget
// (docs/scheduler.md, "Loop limits") is shared by all loops nested in an
// outermost loop and is not renewed while it runs: once spent, the loop that
// is running ends early and so does every enclosing loop at its next turn.
// Budgets are kept per group of SIMD lanes, so some threads of a workgroup may
// leave the persistent loop while the others stay, which puts the barriers
// out of step and corrupts items. Whatever was cut, the threads that left
// early know it here, and the run fails with RunError::LoopLimit instead of
// returning wrong results.
fn sched_check_left_in_step(ended_by_condition: bool) {
    if (!ended_by_condition) {
        atomicAdd(&sched_control[SCHED_CTRL_LOOPS_CUT], 1u);
    }
}

// All threads, right after each body call: whether the driver's loop budget
// (llvmpipe, docs/scheduler.md "Loop limits") ran out inside the body. The
// budget is checked at each loop's back edge, so this loop of two turns (its
// count comes from the uniform, so it cannot be unrolled) runs its second
// turn only while budget is left. The scheduler's own loops around the body
// spend none between the body's start and here, so a cut found here is the
// body's: counted apart from the scheduler's waits.
fn sched_check_body_loops() {
    let turns = sched_config[SCHED_NUM_QUEUES].w;
    var ran = 0u;
    for (var i = 0u; i < turns; i += 1u) {
        ran += 1u;
    }
    if (ran < turns) {
        atomicAdd(&sched_control[SCHED_CTRL_BODY_LOOPS_CUT], 1u);
    }
}

// Thread 0 only: choose the next batch. Returns (queue, first ticket, count, _),
// or SCHED_IDLE / SCHED_EXIT in .x.
fn sched_pick(workgroup: u32, iteration: u32) -> vec4<u32> {
    // A workgroup that spun (waited for slots, or idled) a lot leaves at this
    // batch boundary, so that on llvmpipe its shared loop budget is not spent
    // (docs/scheduler.md, "Loop limits") and elsewhere no wait holds the
    // dispatch for ever. The host dispatches again while work is
    // outstanding, and fails the run when a dispatch makes no progress.
    if (sched_spins > sched_config[SCHED_NUM_QUEUES].y) {
        return vec4<u32>(SCHED_EXIT, 0u, 0u, 0u);
    }
    let start = sched_policy_start(workgroup, iteration);
    for (var i = 0u; i < SCHED_NUM_QUEUES; i += 1u) {
        let q = sched_queue_order[(start + i) % SCHED_NUM_QUEUES];
        let claim = sched_try_claim(q, sched_items_per_batch[q]);
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
    // Idling is waiting too: it counts against the spin limit, so that no
    // workgroup polls for ever for work that never comes.
    sched_spins += 1u;
    return vec4<u32>(SCHED_IDLE, 0u, 0u, 0u);
}

// Consumer side, all threads, after every thread of the generated runner
// decoded its item straight from the claimed slots (without loops): hand the
// slots back by completing the released range, which waits on nobody. The
// runner puts a storageBarrier (acquire) before its reads; this one is the
// release: the reads complete before the slots are handed back.
fn sched_receive_done(lid: u32, q: u32, first: u32, count: u32) {
    storageBarrier();
    if (lid == 0u && !sched_rounds && count > 0u) {
        sched_complete_range(q, SCHED_Q_RELEASED, sched_capacity(q), first, first + count);
    }
}

// Producer side, all threads, once per batch for all the queues it enqueues
// into: every thread's staging is done, and the consumers' releases seen so
// far are visible. The generated runner then has thread 0 reserve the slots
// of every target queue (sched_reserve), shares the reservations
// (sched_flush_share), copies the staged items and publishes them
// (sched_publish). One set of barriers serves all targets: each barrier is a
// suspension point that llvmpipe compiles at a cost that grows with the code
// around it.
fn sched_flush_begin() {
    workgroupBarrier();
    storageBarrier();
}

// Thread 0 only: reserves slots of queue q for the items this workgroup
// staged for it and returns (first ticket, count).
fn sched_reserve(q: u32, stage_capacity: u32) -> vec2<u32> {
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
            // Our slots last held tickets up to first + accepted - capacity.
            // The capacity test above guarantees those were claimed, and
            // their consumers release them without waiting on producers (nor
            // on this workgroup's reservations in other queues, which it
            // publishes only after all of them).
            // In rounds, `fill` keeps counting the running round's items
            // until the next prepare, so those slots are free already.
            if (!sched_rounds) {
                sched_wait_released(q, first + accepted - cap);
            }
        }
    }
    atomicStore(&sched_wg_staged[q], 0u);
    return vec2<u32>(first, accepted);
}

// All threads, after thread 0 wrote the reservations into sched_wg_flushes:
// the same (first ticket, count) per target in every thread.
fn sched_flush_share() -> array<vec2<u32>, SCHED_MAX_TARGETS> {
    let flushes = workgroupUniformLoad(&sched_wg_flushes);
    // Acquire: the consumers' reads of these slots happen before our writes.
    storageBarrier();
    return flushes;
}

// Thread 0 only, after a storageBarrier that follows the copies (release:
// the payload is complete before `published` covers it): publishes the
// reservation `flush` of queue q.
fn sched_publish(q: u32, flush: vec2<u32>) {
    if (flush.y > 0u && !sched_rounds) {
        sched_complete_range(q, SCHED_Q_PUBLISHED, 0u, flush.x, flush.x + flush.y);
    }
}

// Rounds strategy, between two rounds (one thread, own dispatch): retire the
// round that ran on queue q and snapshot the next one. The round ran tickets
// [head, round_end); they are consumed, so their slots are released and leave
// `fill`. Everything enqueued since is complete (the previous dispatches
// ended), so `published` jumps to `tail` and the next round runs
// [round_end, tail): exactly the items queued before it starts. Writes the
// indirect dispatch size of q and returns the number of items in its round.
fn sched_prepare_queue(q: u32) -> u32 {
    let head = atomicLoad(&sched_control[sched_ctrl(q, SCHED_Q_HEAD)]);
    let end = atomicLoad(&sched_control[sched_ctrl(q, SCHED_Q_ROUND_END)]);
    atomicSub(&sched_control[sched_ctrl(q, SCHED_Q_FILL)], end - head);
    atomicStore(&sched_control[sched_ctrl(q, SCHED_Q_RELEASED)], end);
    atomicStore(&sched_control[sched_ctrl(q, SCHED_Q_HEAD)], end);
    let tail = atomicLoad(&sched_control[sched_ctrl(q, SCHED_Q_TAIL)]);
    atomicStore(&sched_control[sched_ctrl(q, SCHED_Q_PUBLISHED)], tail);
    atomicStore(&sched_control[sched_ctrl(q, SCHED_Q_ROUND_END)], tail);
    let count = tail - end;
    // Clamp to the workgroups the staging buffer has room for, which the host
    // keeps within the device's per-dimension limit: an oversized indirect
    // dispatch would be skipped silently. The round kernels loop over the
    // remaining batches, so the clamp never drops an item.
    let batches = (count + sched_items_per_batch[q] - 1u) / sched_items_per_batch[q];
    sched_dispatch[3u * q] = min(batches, sched_config[SCHED_NUM_QUEUES].z);
    sched_dispatch[3u * q + 1u] = 1u;
    sched_dispatch[3u * q + 2u] = 1u;
    return count;
}

// Rounds strategy, thread 0 of a round workgroup: the round's range of queue q
// as (first ticket, count).
fn sched_round_range(q: u32) -> vec2<u32> {
    let head = atomicLoad(&sched_control[sched_ctrl(q, SCHED_Q_HEAD)]);
    let end = atomicLoad(&sched_control[sched_ctrl(q, SCHED_Q_ROUND_END)]);
    return vec2<u32>(head, end - head);
}

// First staging word of the `index`-th item staged for a queue.
fn sched_stage_word(stage_offset: u32, words: u32, index: u32) -> u32 {
    return sched_wg_base + stage_offset + index * words;
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
    return sched_stage_word(stage_offset, sched_slot_words[q], index);
}

// Staging packets: `word` is a staging word index, a multiple of 4.
fn sched_staging_load4(word: u32) -> vec4<u32> {
    return sched_staging[word / 4u];
}
fn sched_staging_store4(word: u32, value: vec4<u32>) {
    sched_staging[word / 4u] = value;
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
