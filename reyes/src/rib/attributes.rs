//! `Attribute` and `Opacity`: the displacement bound, and attributes the
//! renderer cannot apply, checked and warned about (with their lines)
//! rather than passed over in silence.

use std::path::Path;

use super::interp::Interp;
use super::parser::Value;
use super::state;

impl Interp {
    /// `Attribute "class" "name" value ...`. `"displacementbound"` is
    /// checked (`"sphere"` a finite radius >= 0, `"coordinatesystem"` a
    /// string) and bounds the displacement shaders of the primitives that
    /// follow (`Interp::displacement_bound`). Other classes warn once each.
    pub(super) fn attribute(
        &mut self,
        v: &[Value],
        file: &Path,
        line: usize,
    ) -> Result<(), String> {
        let class = state::arg_str(v, 0, "the attribute class")?;
        if v.len() % 2 != 1 {
            return Err(format!(
                "Attribute {class:?}: parameters come in name-value pairs"
            ));
        }
        if class != "displacementbound" {
            self.warn_once(
                &format!("Attribute {class}"),
                file,
                line,
                format!("Attribute {class:?} is not supported; ignored"),
            );
            return Ok(());
        }
        let mut radius = None;
        let mut space = None;
        for pair in v[1..].chunks(2) {
            let name = pair[0]
                .str()
                .ok_or("Attribute \"displacementbound\": a parameter name must be a string")?;
            // An inline declaration ("float sphere") names the same parameter.
            match name.rsplit(' ').next().unwrap_or(name) {
                "sphere" => {
                    let r = pair[1]
                        .nums()
                        .filter(|n| n.len() == 1)
                        .ok_or("Attribute \"displacementbound\" \"sphere\" takes one number")?[0];
                    if !(r.is_finite() && r >= 0.0) {
                        return Err(format!(
                            "Attribute \"displacementbound\" \"sphere\" {r}: the radius must be finite and >= 0"
                        ));
                    }
                    radius = Some(r);
                }
                "coordinatesystem" => {
                    space = Some(pair[1].str().ok_or(
                        "Attribute \"displacementbound\" \"coordinatesystem\" takes a string",
                    )?);
                }
                other => self.warn(
                    file,
                    line,
                    format!("Attribute \"displacementbound\" {other:?} is not a displacementbound parameter; ignored"),
                ),
            }
        }
        if let Some(radius) = radius {
            let space = space.map(str::to_owned);
            self.displacement_bound(radius, space.as_deref(), file, line);
        }
        Ok(())
    }

    /// `Opacity [r g b]`: checked; surfaces are opaque.
    pub(super) fn opacity(&mut self, v: &[Value], file: &Path, line: usize) -> Result<(), String> {
        let n = state::all_nums(v, 3)?;
        if n != [1.0, 1.0, 1.0] {
            self.warn_once(
                "Opacity",
                file,
                line,
                format!(
                    "Opacity [{} {} {}]: transparency is not supported; surfaces are opaque",
                    n[0], n[1], n[2]
                ),
            );
        }
        Ok(())
    }
}
