// Displacement: the height sources (grey height map, built-in sines),
// displacement shaders (user_displacement, which also runs users' WGSL
// height functions) and the normals displacement needs. Every function
// mirrors reyes::displacement and reyes::reference::displace operation for
// operation. DISPLACE_*, TAU and SINES_* are generated from the Rust side.

// i modulo n, in 0..n also for negative i (reyes::displacement::height_map::wrap).
fn wrap_index(i: i32, n: u32) -> u32 {
    let m = i32(n);
    return u32(((i % m) + m) % m);
}

fn map_texel(o: Object, i: u32, j: u32) -> f32 {
    return height_texels[o.map_offset + j * o.map_width + i];
}

// HeightMap::sample: bilinear, wrapping around; texel (i, j) is centred at
// ((i + 0.5) / width, (j + 0.5) / height).
fn height_image(o: Object, u: f32, v: f32) -> f32 {
    let x = u * f32(o.map_width) - 0.5;
    let y = v * f32(o.map_height) - 0.5;
    let x0 = floor(x);
    let y0 = floor(y);
    let fx = x - x0;
    let fy = y - y0;
    let i0 = wrap_index(i32(x0), o.map_width);
    let j0 = wrap_index(i32(y0), o.map_height);
    let i1 = (i0 + 1u) % o.map_width;
    let j1 = (j0 + 1u) % o.map_height;
    let top = map_texel(o, i0, j0) + (map_texel(o, i1, j0) - map_texel(o, i0, j0)) * fx;
    let bottom = map_texel(o, i0, j1) + (map_texel(o, i1, j1) - map_texel(o, i0, j1)) * fx;
    return top + (bottom - top) * fy;
}

// reyes::displacement::sines::wave: -sin(2 pi x) with the argument reduced
// to [-pi, pi) first.
fn sine_wave(x: f32) -> f32 {
    return sin(TAU * ((x - floor(x)) - 0.5));
}

// reyes::displacement::sines::sines: two octaves of egg-crate bumps, zero on
// integer u or v, |h| <= 1.
fn height_sines(u: f32, v: f32) -> f32 {
    let first = sine_wave(u) * sine_wave(v);
    let second = sine_wave(SINES_OCTAVE_2_FREQUENCY * u) * sine_wave(SINES_OCTAVE_2_FREQUENCY * v);
    return (first + SINES_OCTAVE_2_WEIGHT * second) * SINES_NORMALIZATION;
}

// PreparedDisplacement::height: the source at (tiling * u, tiling * v).
fn displacement_height(o: Object, u: f32, v: f32) -> f32 {
    let tu = u * o.tiling;
    let tv = v * o.tiling;
    switch o.displace_kind {
        case DISPLACE_IMAGE: {
            return height_image(o, tu, tv);
        }
        case DISPLACE_SINES: {
            return height_sines(tu, tv);
        }
        default: {
            return 0.0;
        }
    }
}

// reyes::reference::dice::displacement_normal: normalize(dP/ds x dP/dt),
// not turned to the eye, re-evaluated at the clamped parameters when
// degenerate, zero when that is degenerate too.
fn displacement_normal(p: ptr<function, array<f32, 48>>, s: f32, t: f32) -> vec3<f32> {
    var n = tangent_normal(p, s, t);
    if (all(n == vec3<f32>(0.0))) {
        n = tangent_normal(
            p,
            clamp(s, DEGENERATE_PARAM_MIN, DEGENERATE_PARAM_MAX),
            clamp(t, DEGENERATE_PARAM_MIN, DEGENERATE_PARAM_MAX),
        );
    }
    return normalize_or_zero(n);
}

// reyes::reference::displace::lerp_param.
fn lerp_param(a: f32, b: f32, s: f32) -> f32 {
    return a + (b - a) * s;
}

// reyes::reference::displace::displacement_context: what a displacement
// shader sees at (u, v) of input patch `input_patch` (`q`): the undisplaced
// point, N = Ng its exact unit normal on the model's side, and no grid step
// (du = dv = 0): a displaced point depends on (u, v) alone, so that grids
// sharing an edge agree on it.
fn displacement_context(q: ptr<function, array<f32, 48>>, input_patch: u32, object: Object, position: vec3<f32>, u: f32, v: f32) -> ShadingContext {
    let normal = displacement_normal(q, u, v) * object.displace_orientation;
    let to_eye = towards_eye(position);
    let st = patch_st_frame(input_patch, u, v);
    return ShadingContext(
        position,
        normal,
        normal,
        -to_eye,
        position + to_eye,
        u,
        v,
        0.0,
        0.0,
        st.st.x,
        st.st.y,
        tangent_s(q, u, bernstein(v)),
        tangent_t(q, bernstein(u), v),
        st.dstdu,
        st.dstdv,
        object.color.xyz,
        vec3<f32>(1.0),
        0.0,
    );
}

// reyes::reference::displace::displaced_point: the input patch at (u, v),
// moved along the exact normal by the height times the scale, or where the
// object's displacement shader puts it (its offset times the scale), when
// the object is displaced.
fn displaced_point(q: ptr<function, array<f32, 48>>, object: Object, input_patch: u32, u: f32, v: f32) -> vec3<f32> {
    let position = patch_position(q, u, v);
    if (VARIANT_DISPLACED) {
        if (DISPLACEMENT_SHADERS) {
            if (object.displace_kind == DISPLACE_SHADER) {
                let ctx = displacement_context(q, input_patch, object, position, u, v);
                let moved = user_displacement(object.displace_shader, ctx, object.displace_parameters);
                return position + (moved - position) * object.displace_scale;
            }
        }
        if (object.displace_kind != DISPLACE_NONE) {
            let offset = displacement_height(object, u, v) * object.displace_scale;
            return position + displacement_normal(q, u, v) * offset;
        }
    }
    return position;
}

// reyes::reference::displace::grid_normal at point (i, j) of a grid of nu x
// nv micropolygons over `uv`: normalize(dS x dT) from the displaced
// neighbours (central differences, one-sided at the grid's edges), each
// evaluated here; not yet facing the eye; zero when degenerate.
fn displaced_grid_normal(q: ptr<function, array<f32, 48>>, object: Object, input_patch: u32, uv: vec4<f32>, nu: u32, nv: u32, i: u32, j: u32) -> vec3<f32> {
    let u = grid_param(uv.x, uv.z, i, nu);
    let v = grid_param(uv.y, uv.w, j, nv);
    let u_next = grid_param(uv.x, uv.z, min(i + 1u, nu), nu);
    let u_prev = grid_param(uv.x, uv.z, max(i, 1u) - 1u, nu);
    let v_next = grid_param(uv.y, uv.w, min(j + 1u, nv), nv);
    let v_prev = grid_param(uv.y, uv.w, max(j, 1u) - 1u, nv);
    let d_s = displaced_point(q, object, input_patch, u_next, v) - displaced_point(q, object, input_patch, u_prev, v);
    let d_t = displaced_point(q, object, input_patch, u, v_next) - displaced_point(q, object, input_patch, u, v_prev);
    let n = cross3(d_s, d_t);
    if (degenerate(n, d_s, d_t)) {
        return vec3<f32>(0.0);
    }
    return normalize_or_zero(n);
}
