//! Procedural macros of the `scheduler` crate; use them through `scheduler`
//! (`#[derive(scheduler::Item)]`, `#[scheduler::item]`), whose `Item` trait
//! documents what they generate and the layout rules they check.

mod attribute;
mod derive;
mod types;

use proc_macro::TokenStream;
use syn::{DeriveInput, parse_macro_input};

/// Derives `scheduler::Item` (and `scheduler::WgslType`) for a `#[repr(C)]`
/// struct with named fields, generating its WGSL struct and asserting at
/// compile time that Rust and WGSL lay it out identically. The type must also
/// be `bytemuck::Pod`; `#[scheduler::item]` derives that too.
/// `#[wgsl(name = "Name")]` on the struct sets a WGSL name other than the
/// Rust one.
#[proc_macro_derive(Item, attributes(wgsl))]
pub fn derive_item(input: TokenStream) -> TokenStream {
    let input = parse_macro_input!(input as DeriveInput);
    derive::expand(&input)
        .unwrap_or_else(syn::Error::into_compile_error)
        .into()
}

/// Makes a struct an item in one line: adds `#[repr(C)]` when missing and
/// derives `Clone`, `Copy`, `bytemuck::Pod`, `bytemuck::Zeroable` (through
/// `scheduler::bytemuck`, so the user crate needs no `bytemuck` dependency)
/// and `scheduler::Item`, skipping those the struct already derives.
#[proc_macro_attribute]
pub fn item(attribute: TokenStream, input: TokenStream) -> TokenStream {
    let input = parse_macro_input!(input as DeriveInput);
    attribute::expand(attribute.into(), &input)
        .unwrap_or_else(syn::Error::into_compile_error)
        .into()
}
