//! Object instancing: `ObjectBegin` ... `ObjectEnd` records a definition's
//! primitives in the definition's own space, and `ObjectInstance` places
//! them with the transform and the attributes in force at the instance
//! (RenderMan's rule: an instance takes the current attributes).
//!
//! Each instance becomes one object whose model is the definition's
//! patches and whose placement is a general matrix
//! ([`crate::scene::Transform::matrix`]), so instances of one definition
//! have equal models and the GPU stores their patches once
//! ([`crate::prepare::PatchStore`]). An instance under motion blur, or one
//! whose placed points leave `f32`, is baked into world space like any
//! other primitive instead.
//!
//! Definitions hold only geometry: the attributes and lights requested
//! inside one apply to nothing after it (their blocks restore them). A
//! definition lives to the end of the file; redefining a name replaces it.

use std::path::{Path, PathBuf};

use glam::{DMat4, Vec2, Vec3};

use super::interp::{Interp, Prim, RequestError, camera_to_world};
use super::parser::Value;
use super::state::Xform;

/// A recorded object: every patch of its primitives, in its own space.
#[derive(Debug, Clone, Default)]
pub(super) struct Definition {
    /// The control points, in the space of the definition.
    pub(super) patches: Vec<[Vec3; 16]>,
    /// Each patch's corner texture coordinates.
    pub(super) st: Vec<[Vec2; 4]>,
}

/// The definition being recorded and what it set aside.
#[derive(Debug)]
pub(super) struct OpenDefinition {
    /// Its name.
    name: String,
    /// The primitives made before it, restored at `ObjectEnd`.
    outer_prims: Vec<Prim>,
    /// The transform in force at `ObjectBegin`, restored at `ObjectEnd`.
    outer_xf: Xform,
}

/// An object's name: RIB 3.2's sequence number or a later RIB's string.
fn object_name(v: &[Value], request: &str) -> Result<String, String> {
    match v.first() {
        Some(Value::Num(n)) => Ok(format!("{n}")),
        Some(Value::Str(s)) => Ok(s.clone()),
        Some(Value::Nums(n)) if n.len() == 1 => Ok(format!("{}", n[0])),
        Some(Value::Strs(s)) if s.len() == 1 => Ok(s[0].clone()),
        _ => Err(format!(
            "{request} needs the object's name (a number or a string)"
        )),
    }
}

impl Interp {
    /// Whether an object definition is being recorded: its geometry stays
    /// in the definition's space.
    pub(super) fn defining_object(&self) -> bool {
        self.defining.is_some()
    }

    /// `ObjectBegin name`: starts recording a definition, in a space of its
    /// own (the identity transform).
    pub(super) fn object_begin(&mut self, v: &[Value]) -> Result<(), String> {
        let name = object_name(v, "ObjectBegin")?;
        if let Some(open) = &self.defining {
            return Err(format!(
                "inside the definition of object {:?}: definitions do not nest",
                open.name
            ));
        }
        if self.motion.is_some() {
            return Err("inside MotionBegin: a definition is no transform".into());
        }
        let outer_xf = std::mem::take(&mut self.xf);
        self.defining = Some(OpenDefinition {
            name,
            outer_prims: std::mem::take(&mut self.prims),
            outer_xf,
        });
        Ok(())
    }

    /// `ObjectEnd`: keeps the definition under its name and restores the
    /// primitives and the transform of its `ObjectBegin`.
    pub(super) fn object_end(&mut self) -> Result<(), String> {
        // The structure check matched it to an ObjectBegin; one that failed
        // to open (a nested one) left nothing to close.
        let Some(open) = self.defining.take() else {
            return Ok(());
        };
        let prims = std::mem::replace(&mut self.prims, open.outer_prims);
        self.xf = open.outer_xf;
        let mut definition = Definition::default();
        for prim in prims {
            definition.patches.extend(prim.patches);
            definition.st.extend(prim.st);
        }
        self.definitions.insert(open.name, definition);
        Ok(())
    }

    /// `ObjectInstance name`: the definition placed by the current
    /// transform, with the current attributes.
    pub(super) fn object_instance(
        &mut self,
        v: &[Value],
        file: &Path,
        line: usize,
    ) -> Result<(), RequestError> {
        let name = object_name(v, "ObjectInstance")?;
        if self.defining.is_some() {
            return Err("inside an object definition: definitions do not nest"
                .to_owned()
                .into());
        }
        let Some(definition) = self.definitions.get(&name).cloned() else {
            let known = if self.definitions.is_empty() {
                "no object is defined".to_owned()
            } else {
                let mut names: Vec<&String> = self.definitions.keys().collect();
                names.sort();
                let shown: Vec<String> = names.iter().take(5).map(|n| format!("{n:?}")).collect();
                format!("defined: {}", shown.join(", "))
            };
            return Err(format!("no object {name:?} ({known})").into());
        };
        if self.camera.is_none() {
            return Err("ObjectInstance before WorldBegin".to_owned().into());
        }
        let count = definition.patches.len();
        self.take_patches(count, || format!("{count} patches of object {name:?}"))?;
        let camera = self.camera.unwrap_or(DMat4::IDENTITY);
        let open = camera_to_world() * camera * self.xf.open;
        let placement = open.as_mat4();
        let placed_finite = definition
            .patches
            .iter()
            .flatten()
            .all(|&p| placement.transform_point3(p).is_finite());
        let moving = self.xf.open != self.xf.close;
        let Definition { patches, st } = definition;
        if moving || !placed_finite || !placement.is_finite() {
            // Baked into world space as any primitive: emit checks the
            // points and says what overflows.
            let patches = patches
                .iter()
                .map(|patch| patch.map(|p| p.as_dvec3()))
                .collect();
            let st = st.iter().map(|c| c.map(|c| c.as_dvec2())).collect();
            return self.emit("ObjectInstance", patches, st, file, line);
        }
        self.lights_for_primitive();
        self.prims.push(Prim {
            patches,
            st,
            attrs: self.attrs.clone(),
            close: None,
            request: "ObjectInstance",
            file: PathBuf::from(file),
            line,
            placement: Some(placement),
        });
        Ok(())
    }
}
