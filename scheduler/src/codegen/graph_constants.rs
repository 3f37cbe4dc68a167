//! The declarations of the graph's constants ([`Graph::constant`](crate::Graph::constant)):
//! each value writes its own WGSL type and literal
//! ([`ConstantValue`]); this places them in the module.

use crate::ConstantValue;
use crate::codegen::module::Constant;

/// The declarations of checked constants, in declaration order.
pub(crate) fn declarations(constants: &[(String, ConstantValue)]) -> Vec<Constant> {
    constants
        .iter()
        .enumerate()
        .filter_map(|(i, (name, value))| {
            Some(Constant {
                name: name.clone(),
                ty: value.wgsl_type().to_owned(),
                value: value.wgsl_literal()?,
                doc: if i == 0 {
                    "Graph constants (`Graph::constant`).".to_owned()
                } else {
                    String::new()
                },
            })
        })
        .collect()
}
