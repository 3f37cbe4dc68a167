//! `#[gpu_test]`, the attribute of the workspace's GPU tests. The contract
//! it implements is documented on the `gpu-test` crate, which re-exports it.

use proc_macro::TokenStream;
use proc_macro2::TokenStream as TokenStream2;
use quote::{quote, quote_spanned};
use syn::meta::ParseNestedMeta;
use syn::parse::Parser;
use syn::{FnArg, ItemFn, LitInt, LitStr};

/// Marks a GPU test: `#[test]`, reported `ignored` under `SKIP_GPU_TESTS=1`
/// (the `skip_gpu_tests` cfg the crate's build script sets through
/// `gpu_test::build`).
///
/// The function takes no argument, or one `&Gpu` (the shared device).
/// `expect_fail(...)` declares a driver on which the test is known to fail,
/// with the keys `backend`, `vendor`, `adapter`, `driver` (which adapters it
/// covers: all of them when none is given), `message` (a substring the panic
/// message must contain) and `reason` (required: why it fails there); the
/// attribute may declare several.
#[proc_macro_attribute]
pub fn gpu_test(args: TokenStream, item: TokenStream) -> TokenStream {
    let function = syn::parse_macro_input!(item as ItemFn);
    let mut cases = Vec::new();
    let parser = syn::meta::parser(|meta| {
        if meta.path.is_ident("expect_fail") {
            cases.push(failure_case(&meta)?);
            Ok(())
        } else {
            Err(meta.error("expected `expect_fail(...)`"))
        }
    });
    if let Err(error) = parser.parse(args) {
        return error.to_compile_error().into();
    }
    match expand(function, &cases) {
        Ok(tokens) => tokens.into(),
        Err(error) => error.to_compile_error().into(),
    }
}

/// One `expect_fail(key = value, ...)` as a `gpu_test::FailureCase`
/// expression.
fn failure_case(meta: &ParseNestedMeta) -> syn::Result<TokenStream2> {
    let mut fields = Vec::new();
    let mut reason = None;
    meta.parse_nested_meta(|key| {
        let Some(field) = key.path.get_ident().cloned() else {
            return Err(key.error("expected a key such as `driver`"));
        };
        match field.to_string().as_str() {
            "backend" | "adapter" | "driver" | "message" => {
                let value: LitStr = key.value()?.parse()?;
                fields.push(quote! { #field: ::core::option::Option::Some(#value), });
            }
            "vendor" => {
                let value: LitInt = key.value()?.parse()?;
                fields.push(quote! { vendor: ::core::option::Option::Some(#value), });
            }
            "reason" => reason = Some(key.value()?.parse::<LitStr>()?),
            _ => {
                return Err(key.error(
                    "expected `backend`, `vendor`, `adapter`, `driver`, `message` or `reason`",
                ));
            }
        }
        Ok(())
    })?;
    let reason = reason
        .ok_or_else(|| meta.error("`expect_fail` needs a `reason = \"...\"`: why it fails"))?;
    Ok(quote! {
        ::gpu_test::FailureCase { #(#fields)* ..::gpu_test::FailureCase::always(#reason) }
    })
}

fn expand(function: ItemFn, cases: &[TokenStream2]) -> syn::Result<TokenStream2> {
    let ItemFn {
        attrs,
        vis,
        sig,
        block,
    } = function;
    let name = &sig.ident;
    let skip_mark = quote! {
        #[test]
        #[cfg_attr(skip_gpu_tests, ignore = "SKIP_GPU_TESTS=1")]
    };
    let takes_gpu = match sig.inputs.len() {
        0 => false,
        1 if matches!(sig.inputs[0], FnArg::Typed(_)) => true,
        _ => {
            return Err(syn::Error::new_spanned(
                &sig.inputs,
                "a GPU test takes no argument, or one `&Gpu`",
            ));
        }
    };
    let call = if takes_gpu {
        quote_spanned! { name.span()=> #name }
    } else {
        quote! { |_| #name() }
    };
    let outer_sig = syn::Signature {
        inputs: Default::default(),
        ..sig.clone()
    };
    Ok(quote! {
        #(#attrs)*
        #skip_mark
        #vis #outer_sig {
            #sig #block
            ::gpu_test::GpuTest::new(::core::concat!(
                ::core::module_path!(), "::", ::core::stringify!(#name)
            ))
            #(.expect_fail(#cases))*
            .run(#call)
        }
    })
}
