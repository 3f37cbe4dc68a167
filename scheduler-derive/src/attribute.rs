//! `#[item]`: one attribute in place of `#[repr(C)]` and five derives.
//!
//! A derive cannot add attributes to the item it derives for, so it cannot
//! point bytemuck's derives at `scheduler::bytemuck` (which needs
//! `#[bytemuck(crate = ...)]`). An attribute macro rewrites the item and can:
//! the user crate then needs neither a `bytemuck` dependency nor `unsafe`,
//! since `Pod` is still implemented, and its soundness checked, by bytemuck.

use proc_macro2::TokenStream;
use quote::quote;
use syn::DeriveInput;
use syn::punctuated::Punctuated;

pub(crate) fn expand(attribute: TokenStream, input: &DeriveInput) -> syn::Result<TokenStream> {
    if !attribute.is_empty() {
        return Err(syn::Error::new_spanned(
            attribute,
            "#[item] takes no arguments",
        ));
    }
    let derived = derived_names(input)?;
    let wanted = [
        ("Clone", quote!(::core::clone::Clone)),
        ("Copy", quote!(::core::marker::Copy)),
        ("Pod", quote!(::scheduler::bytemuck::Pod)),
        ("Zeroable", quote!(::scheduler::bytemuck::Zeroable)),
        ("Item", quote!(::scheduler::Item)),
    ];
    let added: Vec<&TokenStream> = wanted
        .iter()
        .filter(|(name, _)| !derived.iter().any(|d| d == name))
        .map(|(_, path)| path)
        .collect();
    let adds_bytemuck = ["Pod", "Zeroable"]
        .iter()
        .any(|name| !derived.iter().any(|d| d == name));
    let names_crate = input.attrs.iter().any(|a| a.path().is_ident("bytemuck"));
    let bytemuck = (adds_bytemuck && !names_crate)
        .then(|| quote!(#[bytemuck(crate = "::scheduler::bytemuck")]));
    let has_repr = input.attrs.iter().any(|a| a.path().is_ident("repr"));
    let repr = (!has_repr).then(|| quote!(#[repr(C)]));
    let derive = (!added.is_empty()).then(|| quote!(#[derive(#(#added),*)]));
    Ok(quote! {
        #derive
        #bytemuck
        #repr
        #input
    })
}

/// The last path segment of everything the item already derives.
fn derived_names(input: &DeriveInput) -> syn::Result<Vec<String>> {
    let mut names = Vec::new();
    for attribute in input.attrs.iter().filter(|a| a.path().is_ident("derive")) {
        let paths =
            attribute.parse_args_with(Punctuated::<syn::Path, syn::Token![,]>::parse_terminated)?;
        names.extend(
            paths
                .iter()
                .filter_map(|p| p.segments.last().map(|s| s.ident.to_string())),
        );
    }
    Ok(names)
}
