// The user displacement function when the scene has none: the megakernel
// always calls `displacement_user` for DISPLACE_USER objects, and there are
// none. A scene's own function replaces this file (reyes::gpu::graph).
fn displacement_user(u: f32, v: f32) -> f32 {
    return 0.0;
}
