// ---- item-wide helpers (shaders/scheduler/item_helpers.wgsl) ----
// Reductions and broadcasts over the threads of one item. The generator adds
// this block, the workgroup array `sched_wg_item` (one word per thread) and
// `sched_item_reduce` only to modules whose bodies or library call a helper.
//
// Contract: every thread of the workgroup calls the same helpers in the same
// order, at the top level of the body (they contain workgroup barriers), with
// or without an item. The threads of one slot are all valid or all invalid,
// so threads without an item reduce among themselves: they never change the
// result of another item, and their own result is meaningless. Each thread
// gets the result of its own item.

// Operations of sched_item_reduce / sched_item_combine.
const SCHED_ITEM_MIN_U32: u32 = 0u;
const SCHED_ITEM_MAX_U32: u32 = 1u;
const SCHED_ITEM_SUM_U32: u32 = 2u;
const SCHED_ITEM_MIN_I32: u32 = 3u;
const SCHED_ITEM_MAX_I32: u32 = 4u;
const SCHED_ITEM_SUM_I32: u32 = 5u;
const SCHED_ITEM_MIN_F32: u32 = 6u;
const SCHED_ITEM_MAX_F32: u32 = 7u;
const SCHED_ITEM_SUM_F32: u32 = 8u;

// Combines two words as the values of `op` (u32, i32 or f32 bits).
fn sched_item_combine(op: u32, a: u32, b: u32) -> u32 {
    switch op {
        case 0u: { return min(a, b); }
        case 1u: { return max(a, b); }
        case 2u: { return a + b; }
        case 3u: { return bitcast<u32>(min(bitcast<i32>(a), bitcast<i32>(b))); }
        case 4u: { return bitcast<u32>(max(bitcast<i32>(a), bitcast<i32>(b))); }
        case 5u: { return bitcast<u32>(bitcast<i32>(a) + bitcast<i32>(b)); }
        case 6u: { return bitcast<u32>(min(bitcast<f32>(a), bitcast<f32>(b))); }
        case 7u: { return bitcast<u32>(max(bitcast<f32>(a), bitcast<f32>(b))); }
        default: { return bitcast<u32>(bitcast<f32>(a) + bitcast<f32>(b)); }
    }
}

// The value of thread 0 of the calling thread's item, in every thread of it.
fn sched_item_first(value: u32) -> u32 {
    // Readers of an earlier helper are done before the array is overwritten.
    workgroupBarrier();
    sched_wg_item[sched_item_lid] = value;
    workgroupBarrier();
    return sched_wg_item[sched_item_lid - sched_item_lid % sched_item_threads];
}

// Minimum, maximum and sum over the item's threads. Sums of u32 and i32
// wrap; sums of f32 add in a fixed tree order (pairs `stride` apart, the
// stride halving from threads_per_item / 2 down to 1).
fn item_min_u32(value: u32) -> u32 {
    return sched_item_reduce(value, SCHED_ITEM_MIN_U32);
}
fn item_max_u32(value: u32) -> u32 {
    return sched_item_reduce(value, SCHED_ITEM_MAX_U32);
}
fn item_sum_u32(value: u32) -> u32 {
    return sched_item_reduce(value, SCHED_ITEM_SUM_U32);
}
fn item_min_i32(value: i32) -> i32 {
    return bitcast<i32>(sched_item_reduce(bitcast<u32>(value), SCHED_ITEM_MIN_I32));
}
fn item_max_i32(value: i32) -> i32 {
    return bitcast<i32>(sched_item_reduce(bitcast<u32>(value), SCHED_ITEM_MAX_I32));
}
fn item_sum_i32(value: i32) -> i32 {
    return bitcast<i32>(sched_item_reduce(bitcast<u32>(value), SCHED_ITEM_SUM_I32));
}
fn item_min_f32(value: f32) -> f32 {
    return bitcast<f32>(sched_item_reduce(bitcast<u32>(value), SCHED_ITEM_MIN_F32));
}
fn item_max_f32(value: f32) -> f32 {
    return bitcast<f32>(sched_item_reduce(bitcast<u32>(value), SCHED_ITEM_MAX_F32));
}
fn item_sum_f32(value: f32) -> f32 {
    return bitcast<f32>(sched_item_reduce(bitcast<u32>(value), SCHED_ITEM_SUM_F32));
}

// Whether every thread of the item passed the same value.
fn item_all_equal_u32(value: u32) -> bool {
    let first = sched_item_first(value);
    return sched_item_reduce(select(0u, 1u, value == first), SCHED_ITEM_MIN_U32) == 1u;
}

// Whether the condition holds in every thread, or in any thread, of the item.
fn item_all(condition: bool) -> bool {
    return sched_item_reduce(select(0u, 1u, condition), SCHED_ITEM_MIN_U32) == 1u;
}
fn item_any(condition: bool) -> bool {
    return sched_item_reduce(select(0u, 1u, condition), SCHED_ITEM_MAX_U32) == 1u;
}

// Thread 0's value, in every thread of the item.
fn item_broadcast_u32(value: u32) -> u32 {
    return sched_item_first(value);
}
fn item_broadcast_i32(value: i32) -> i32 {
    return bitcast<i32>(sched_item_first(bitcast<u32>(value)));
}
fn item_broadcast_f32(value: f32) -> f32 {
    return bitcast<f32>(sched_item_first(bitcast<u32>(value)));
}
