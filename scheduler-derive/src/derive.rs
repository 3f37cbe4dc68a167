//! `#[derive(Item)]`: the WGSL struct of a Rust struct, and compile-time
//! assertions that both have the same size and field offsets.
//!
//! The WGSL layout is computed by const functions of `scheduler::wgsl_layout`
//! from each field type's `WgslType::WGSL_ALIGN` and `WGSL_SIZE`, so nested
//! items and arrays compose; the assertions compare it with Rust's
//! `offset_of!` and `size_of` when the user crate compiles.

use proc_macro2::TokenStream;
use quote::{ToTokens, quote, quote_spanned};
use syn::ext::IdentExt;
use syn::spanned::Spanned;
use syn::{Data, DeriveInput, Fields, Ident, Type};

use crate::types;

/// One checked field.
struct Field<'a> {
    ident: &'a Ident,
    name: String,
    ty: &'a Type,
    /// The field's `///` documentation, emitted as WGSL comments.
    doc: String,
}

pub(crate) fn expand(input: &DeriveInput) -> syn::Result<TokenStream> {
    let name = &input.ident;
    let wgsl_name = wgsl_name(input)?.unwrap_or_else(|| name.unraw().to_string());
    require_repr_c(input)?;
    if !input.generics.params.is_empty() {
        return Err(syn::Error::new(
            input.generics.span(),
            "#[derive(Item)]: generic structs are not supported; a WGSL struct has one layout",
        ));
    }
    let fields = fields(input)?;

    let krate = quote!(::scheduler);
    let wgsl_type = quote!(#krate::WgslType);
    let layout = quote!(#krate::wgsl_layout);
    let tys: Vec<&Type> = fields.iter().map(|f| f.ty).collect();
    let idents: Vec<&Ident> = fields.iter().map(|f| f.ident).collect();
    let names: Vec<&str> = fields.iter().map(|f| f.name.as_str()).collect();
    let docs: Vec<&str> = fields.iter().map(|f| f.doc.as_str()).collect();

    let assertions = fields.iter().enumerate().map(|(index, field)| {
        let (ident, ty) = (field.ident, field.ty);
        let shown = type_text(ty);
        let size_message = format!(
            "#[derive(Item)]: field `{}` of `{wgsl_name}`: `{shown}` has a different size in Rust than in WGSL",
            field.name
        );
        let offset_message = format!(
            "#[derive(Item)]: field `{}` of `{wgsl_name}` starts at a different byte offset in Rust than in WGSL, which aligns `{shown}` to its WGSL alignment; add explicit padding fields before it (e.g. `_pad: [u32; 2]`)",
            field.name
        );
        quote_spanned! {ty.span()=>
            assert!(
                ::core::mem::size_of::<#ty>() == <#ty as #wgsl_type>::WGSL_SIZE,
                #size_message
            );
            assert!(
                #layout::field_offset(FIELDS, #index) == ::core::mem::offset_of!(#name, #ident),
                #offset_message
            );
        }
    });
    let size_message = format!(
        "#[derive(Item)]: `{wgsl_name}` has a different size in Rust than in WGSL, which rounds a struct's size up to a multiple of its largest field alignment; add padding fields at the end"
    );

    Ok(quote! {
        impl #wgsl_type for #name {
            const WGSL_ALIGN: usize =
                #layout::struct_align(&[#(<#tys as #wgsl_type>::WGSL_ALIGN),*]);
            const WGSL_SIZE: usize = #layout::struct_size(
                &[#((<#tys as #wgsl_type>::WGSL_ALIGN, <#tys as #wgsl_type>::WGSL_SIZE)),*],
            );

            fn wgsl_type() -> ::std::string::String {
                ::std::string::String::from(#wgsl_name)
            }

            fn wgsl_structs(structs: &mut #krate::WgslStructs) {
                #(<#tys as #wgsl_type>::wgsl_structs(structs);)*
                structs.push(#wgsl_name, <Self as #krate::Item>::wgsl_struct());
            }
        }

        impl #krate::Item for #name {
            const WGSL_NAME: &'static str = #wgsl_name;

            fn wgsl_struct() -> ::std::string::String {
                #layout::documented_struct_declaration(
                    #wgsl_name,
                    &[#((#names, <#tys as #wgsl_type>::wgsl_type(), #docs)),*],
                )
            }

            fn rust_fields() -> ::std::vec::Vec<(&'static str, usize)> {
                ::std::vec![#((#names, ::core::mem::offset_of!(#name, #idents))),*]
            }
        }

        const _: () = {
            const FIELDS: &[(usize, usize)] =
                &[#((<#tys as #wgsl_type>::WGSL_ALIGN, <#tys as #wgsl_type>::WGSL_SIZE)),*];
            #(#assertions)*
            assert!(
                <#name as #wgsl_type>::WGSL_SIZE == ::core::mem::size_of::<#name>(),
                #size_message
            );
        };
    })
}

/// The named fields, each with a type that passed the syntactic checks.
fn fields(input: &DeriveInput) -> syn::Result<Vec<Field<'_>>> {
    let named = match &input.data {
        Data::Struct(data) => match &data.fields {
            Fields::Named(named) => named,
            _ => {
                return Err(syn::Error::new(
                    input.ident.span(),
                    "#[derive(Item)]: the struct needs named fields, which become the WGSL field names",
                ));
            }
        },
        _ => {
            return Err(syn::Error::new(
                input.ident.span(),
                "#[derive(Item)] supports structs only",
            ));
        }
    };
    if named.named.is_empty() {
        return Err(syn::Error::new(
            input.ident.span(),
            "#[derive(Item)]: a WGSL struct needs at least one field",
        ));
    }
    let mut fields = Vec::new();
    let mut errors: Option<syn::Error> = None;
    for field in &named.named {
        let Some(ident) = &field.ident else { continue };
        let name = ident.to_string();
        let checked = if name.starts_with("r#") {
            Err(syn::Error::new(
                ident.span(),
                "#[derive(Item)]: raw identifiers are WGSL keywords; rename the field",
            ))
        } else if name.starts_with("__") {
            Err(syn::Error::new(
                ident.span(),
                "#[derive(Item)]: WGSL identifiers may not start with `__`",
            ))
        } else {
            types::check(&field.ty)
        };
        match checked {
            Ok(()) => fields.push(Field {
                ident,
                name,
                ty: &field.ty,
                doc: doc_text(&field.attrs),
            }),
            // Report every bad field at once.
            Err(error) => match &mut errors {
                Some(all) => all.combine(error),
                None => errors = Some(error),
            },
        }
    }
    match errors {
        Some(errors) => Err(errors),
        None => Ok(fields),
    }
}

/// The text of `///` comments (`#[doc = "..."]` attributes), one line each,
/// without the space rustdoc strips.
fn doc_text(attributes: &[syn::Attribute]) -> String {
    let mut lines = Vec::new();
    for attribute in attributes.iter().filter(|a| a.path().is_ident("doc")) {
        if let syn::Meta::NameValue(pair) = &attribute.meta
            && let syn::Expr::Lit(syn::ExprLit {
                lit: syn::Lit::Str(text),
                ..
            }) = &pair.value
        {
            lines.extend(text.value().lines().map(|l| l.trim().to_owned()));
        }
    }
    lines.join("\n")
}

/// The WGSL name given by `#[wgsl(name = "Frame")]`, for a Rust struct
/// whose own name would clash or read badly in WGSL.
fn wgsl_name(input: &DeriveInput) -> syn::Result<Option<String>> {
    let mut name = None;
    for attribute in input.attrs.iter().filter(|a| a.path().is_ident("wgsl")) {
        attribute.parse_nested_meta(|meta| {
            if meta.path.is_ident("name") {
                let text: syn::LitStr = meta.value()?.parse()?;
                let value = text.value();
                let valid = value.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
                    && value.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
                if !valid {
                    return Err(syn::Error::new(
                        text.span(),
                        "#[wgsl(name = ...)]: a WGSL struct name is a letter followed by letters, digits or `_`",
                    ));
                }
                name = Some(value);
                Ok(())
            } else {
                Err(meta.error("#[wgsl(...)] takes `name = \"WgslName\"` only"))
            }
        })?;
    }
    Ok(name)
}

/// Rust's default layout may reorder fields; only `repr(C)` fixes the order
/// and the offsets the assertions compare.
fn require_repr_c(input: &DeriveInput) -> syn::Result<()> {
    let mut c = false;
    for attribute in input.attrs.iter().filter(|a| a.path().is_ident("repr")) {
        attribute.parse_nested_meta(|meta| {
            if meta.path.is_ident("C") {
                c = true;
            } else if meta.path.is_ident("packed") {
                return Err(meta.error(
                    "#[derive(Item)]: packed structs have no WGSL layout; add padding fields instead",
                ));
            } else if meta.input.peek(syn::token::Paren) {
                // `align(N)`: allowed, the size assertion decides. Skip its argument.
                let content;
                syn::parenthesized!(content in meta.input);
                let _: TokenStream = content.parse()?;
            }
            Ok(())
        })?;
    }
    if c {
        Ok(())
    } else {
        Err(syn::Error::new(
            input.ident.span(),
            "#[derive(Item)] needs `#[repr(C)]`: Rust's default layout may reorder fields",
        ))
    }
}

/// A type as the user wrote it, for messages (`glam::Vec4`, `[f32; 3]`).
fn type_text(ty: &Type) -> String {
    ty.to_token_stream()
        .to_string()
        .replace(" :: ", "::")
        .replace(":: ", "::")
        .replace(" ;", ";")
        .replace("[ ", "[")
        .replace(" ]", "]")
        .replace(" < ", "<")
        .replace(" >", ">")
}
