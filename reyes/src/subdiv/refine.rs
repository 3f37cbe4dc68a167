//! One Catmull-Clark step over part of a level, with creases.
//!
//! Refining the faces `R` of a level computes, once each:
//! * the face point of every face sharing a vertex with `R` (its 1-ring);
//! * the edge point of every edge at a vertex of `R` (both its faces are
//!   in the 1-ring);
//! * the vertex point of every vertex of `R` (all of them complete).
//!
//! and makes the child quads of the 1-ring whose four vertices were
//! computed. The children of `R` then have complete vertices again, so the
//! next step can refine any of them. A point is computed once per level
//! and shared by every face around it: positions never depend on which
//! face asked for them.
//!
//! The rules are Catmull-Clark's with the sharpness rules of DeRose et al.
//! 1998 as OpenSubdiv applies them ("uniform" creasing): an edge of
//! sharpness `s >= 1` gets the midpoint, `0 < s < 1` blends the smooth and
//! sharp points by `s`; a vertex's rule (smooth, dart, crease, corner)
//! follows from its sharp edges and its own sharpness, and where the rule
//! changes between a level and the next one, the two are blended by the
//! mean sharpness of what turns smooth. Children's sharpness is one less.

use std::collections::HashMap;

use glam::{Vec2, Vec3};

use super::level::{Key, Level, Origin, child_sharpness, edge, is_infinite, key};

/// The vertex rules.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Rule {
    /// No sharp edge (or one: a dart).
    Smooth,
    /// Two sharp edges.
    Crease,
    /// More, or a sharp vertex.
    Corner,
}

fn rule(vertex_sharpness: f32, sharp_edges: usize) -> Rule {
    if vertex_sharpness > 0.0 || sharp_edges > 2 {
        Rule::Corner
    } else if sharp_edges == 2 {
        Rule::Crease
    } else {
        Rule::Smooth
    }
}

/// What a refinement made: the child level and the children of the
/// refined faces (in the order of the faces, four per quad).
pub(super) struct Refined {
    pub level: Level,
    pub children: Vec<u32>,
}

/// Refines the faces `refine` of `parent` (whose vertices must be
/// complete) into the level below; its keys for new vertices use
/// `depth`, the new level's number.
pub(super) fn refine(parent: &Level, refine: &[u32], depth: usize) -> Refined {
    let mut in_vr = vec![false; parent.positions.len()];
    let mut vr = Vec::new();
    for &f in refine {
        for &v in parent.face(f) {
            debug_assert!(parent.complete[v as usize], "refining an incomplete vertex");
            if !in_vr[v as usize] {
                in_vr[v as usize] = true;
                vr.push(v);
            }
        }
    }
    // The 1-ring, the refined faces first.
    let mut in_ring = vec![false; parent.face_count()];
    let mut ring = Vec::new();
    for &f in refine {
        if !in_ring[f as usize] {
            in_ring[f as usize] = true;
            ring.push(f);
        }
    }
    for &v in &vr {
        for &f in parent.faces_of(v) {
            if !in_ring[f as usize] {
                in_ring[f as usize] = true;
                ring.push(f);
            }
        }
    }

    let mut child = Level::default();
    let add = |child: &mut Level, position: Vec3, k: Key, origin: Origin, complete: bool| {
        let index = child.positions.len() as u32;
        child.positions.push(position);
        child.keys.push(k);
        child.origins.push(origin);
        child.complete.push(complete);
        child.vertex_sharpness.push(0.0);
        index
    };
    let new_key = |child: &Level| key(depth, child.positions.len() as u32);

    // Face points.
    let mut face_point = HashMap::with_capacity(ring.len());
    for &f in &ring {
        let complete = parent.face(f).iter().all(|&v| in_vr[v as usize]);
        let k = new_key(&child);
        let i = add(&mut child, parent.centroid(f), k, Origin::Face(f), complete);
        face_point.insert(f, i);
    }
    // Edge points.
    let mut edge_point = HashMap::new();
    for &v in &vr {
        for &f in parent.faces_of(v) {
            let vs = parent.face(f);
            let k = parent.corner_of(f, v);
            for other in [vs[(k + 1) % vs.len()], vs[(k + vs.len() - 1) % vs.len()]] {
                let e = edge(v, other);
                if edge_point.contains_key(&e) {
                    continue;
                }
                let position = edge_point_position(parent, e, &face_point);
                let complete = in_vr[e.0 as usize] && in_vr[e.1 as usize];
                let k = new_key(&child);
                let i = add(&mut child, position, k, Origin::Edge(e.0, e.1), complete);
                edge_point.insert(e, i);
            }
        }
    }
    // Vertex points.
    let mut vertex_point = HashMap::with_capacity(vr.len());
    for &v in &vr {
        let position = vertex_point_position(parent, v, &face_point);
        let i = add(
            &mut child,
            position,
            parent.keys[v as usize],
            Origin::Vertex(v),
            true,
        );
        child.vertex_sharpness[i as usize] = child_sharpness(parent.vertex_sharpness[v as usize]);
        vertex_point.insert(v, i);
    }
    // Sharp halves of parent edges.
    for (&(a, b), &m) in &edge_point {
        let s = child_sharpness(parent.sharpness(a, b));
        if s > 0.0 {
            for end in [a, b] {
                if let Some(&p) = vertex_point.get(&end) {
                    child.edge_sharpness.insert(edge(p, m), s);
                }
            }
        }
    }
    // Child faces: the corners of 1-ring faces at refined vertices.
    child.face_offsets.push(0);
    let mut st = parent.st.as_ref().map(|_| Vec::new());
    let mut children = Vec::with_capacity(refine.len() * 4);
    for (i, &f) in ring.iter().enumerate() {
        let vs = parent.face(f);
        let n = vs.len();
        let face_st = parent.face_st(f);
        for k in 0..n {
            if !in_vr[vs[k] as usize] {
                continue;
            }
            let (prev, next) = (vs[(k + n - 1) % n], vs[(k + 1) % n]);
            let quad = [
                vertex_point[&vs[k]],
                edge_point[&edge(vs[k], next)],
                face_point[&f],
                edge_point[&edge(prev, vs[k])],
            ];
            let index = child.face_count() as u32;
            child.face_vertices.extend_from_slice(&quad);
            child.face_offsets.push(child.face_vertices.len() as u32);
            child.hidden.push(parent.hidden[f as usize]);
            if let (Some(st), Some(s)) = (st.as_mut(), face_st) {
                let centroid = s.iter().copied().sum::<Vec2>() / n as f32;
                st.extend_from_slice(&[
                    s[k],
                    (s[k] + s[(k + 1) % n]) * 0.5,
                    centroid,
                    (s[(k + n - 1) % n] + s[k]) * 0.5,
                ]);
            }
            if i < refine.len() {
                children.push(index);
            }
        }
    }
    child.st = st;
    child.from_vertex = vertex_point;
    child.from_edge = edge_point;
    child.from_face = face_point;
    child.finish();
    Refined {
        level: child,
        children,
    }
}

/// The edge point of edge `e`: the midpoint where it is sharp (or a
/// boundary), Catmull-Clark's smooth point where smooth, a blend between.
fn edge_point_position(parent: &Level, e: (u32, u32), face_point: &HashMap<u32, u32>) -> Vec3 {
    let (a, b) = e;
    let (pa, pb) = (parent.positions[a as usize], parent.positions[b as usize]);
    let mid = (pa + pb) * 0.5;
    let s = parent.sharpness(a, b);
    if s >= 1.0 {
        return mid;
    }
    let faces = (parent.face_with_edge(a, b), parent.face_with_edge(b, a));
    let (Some((f0, _)), Some((f1, _))) = faces else {
        return mid;
    };
    let (c0, c1) = (parent.centroid(f0), parent.centroid(f1));
    debug_assert!(face_point.contains_key(&f0) && face_point.contains_key(&f1));
    let smooth = (pa + pb + c0 + c1) * 0.25;
    if s > 0.0 { smooth.lerp(mid, s) } else { smooth }
}

/// The vertex point of `v` under its rule, blended with the next level's
/// rule where they differ.
fn vertex_point_position(parent: &Level, v: u32, face_point: &HashMap<u32, u32>) -> Vec3 {
    let p = parent.positions[v as usize];
    let edges = parent.edges_of(v);
    let vs = parent.vertex_sharpness[v as usize];
    let sharp = |s: f32| s > 0.0;
    let parent_rule = rule(vs, edges.iter().filter(|e| sharp(e.1)).count());
    let child_rule = rule(
        child_sharpness(vs),
        edges.iter().filter(|e| sharp(child_sharpness(e.1))).count(),
    );
    let mask = |rule: Rule, child: bool| -> Vec3 {
        match rule {
            Rule::Corner => p,
            Rule::Crease => {
                let ends: Vec<Vec3> = edges
                    .iter()
                    .filter(|e| sharp(if child { child_sharpness(e.1) } else { e.1 }))
                    .map(|e| parent.positions[e.0 as usize])
                    .collect();
                (ends[0] + p * 6.0 + ends[1]) * 0.125
            }
            Rule::Smooth => smooth_vertex_point(parent, v, &edges, face_point),
        }
    };
    if parent_rule == child_rule || parent_rule == Rule::Smooth {
        return mask(parent_rule, false);
    }
    let mut sum = 0.0;
    let mut count = 0;
    if vs > 0.0 && child_sharpness(vs) == 0.0 {
        sum += vs;
        count += 1;
    }
    for &(_, s) in &edges {
        if s > 0.0 && child_sharpness(s) == 0.0 {
            sum += s;
            count += 1;
        }
    }
    let weight = if count == 0 {
        0.0
    } else {
        (sum / count as f32).min(1.0)
    };
    debug_assert!(!is_infinite(sum) || count == 0);
    mask(child_rule, true).lerp(mask(parent_rule, false), weight)
}

/// Catmull-Clark's smooth vertex point `(Q + 2R + (n - 3) v) / n`: `Q` the
/// mean of the face points around, `R` of the edge midpoints.
fn smooth_vertex_point(
    parent: &Level,
    v: u32,
    edges: &[(u32, f32)],
    face_point: &HashMap<u32, u32>,
) -> Vec3 {
    let p = parent.positions[v as usize];
    let faces = parent.faces_of(v);
    debug_assert!(faces.iter().all(|f| face_point.contains_key(f)));
    let q = faces.iter().map(|&f| parent.centroid(f)).sum::<Vec3>() / faces.len() as f32;
    let n = edges.len() as f32;
    let r = edges
        .iter()
        .map(|&(w, _)| (p + parent.positions[w as usize]) * 0.5)
        .sum::<Vec3>()
        / n;
    (q + r * 2.0 + p * (n - 3.0)) / n
}
