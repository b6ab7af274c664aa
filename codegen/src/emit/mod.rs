//! Emission of a derived model as a Rust module (quote / proc-macro2, checked by
//! `syn::parse_file`, formatted by `prettyplease`).
//!
//! The module implements `telescopic_runtime::Model` for `GeneratedModel`. Per-scene work
//! (matrices from the parameters, `M^-1`, fixed contact vectors, output vectors) happens in
//! `GeneratedModel::prepare`; the per-call path is straight-line code over fixed-size arrays
//! with the structural zeros of the derivation dropped, and allocates nothing.
//!
//! One function per emitted item, as prost-build's code generator has one `append_*` per
//! item: [`parts`] has the constants, shape functions, contact geometry, forces, Jacobian
//! rows and the code that differs by configuration (moving positions, prescribed motion);
//! [`model`] assembles the struct, its `prepare` and the `Model` impl; [`emit`] formats.

mod model;
mod parts;
mod tokens;

use crate::config::ModelConfig;
use crate::derive::Derivation;
use crate::expr::{Expr, eliminate_common};
use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use tokens::{LINE_COMMENT, line_comment, parameter_bindings, tokens, unsuffixed};

/// A symmetric matrix function from its upper-triangle entries, with common subexpressions
/// as temporaries.
pub(super) fn matrix_fn(
    name: &str,
    doc: &str,
    config: &ModelConfig,
    entries: &[((usize, usize), Expr)],
) -> TokenStream {
    let fname = format_ident!("{}", name);
    let exprs: Vec<Expr> = entries.iter().map(|(_, e)| e.clone()).collect();
    let (temps, exprs) = eliminate_common(&exprs);
    let temp_lets = temps.iter().enumerate().map(|(i, t)| {
        let id = format_ident!("t{}", i);
        let v = tokens(t, &|_| None);
        quote!(let #id = #v;)
    });
    let sets = entries.iter().zip(&exprs).map(|(((i, j), original), e)| {
        let v = tokens(e, &|_| None);
        let comment = format!(" {name}[{i}][{j}] = {}", original.to_text());
        if i == j {
            let note = line_comment(&comment);
            quote! { #note { m[(#i, #j)] = #v; } }
        } else {
            let note = line_comment(&comment);
            quote! { #note { let v = #v; m[(#i, #j)] = v; m[(#j, #i)] = v; } }
        }
    });
    let bindings = parameter_bindings(config);
    quote! {
        #[doc = #doc]
        #[allow(unused_variables)]
        pub fn #fname(p: &ModelParams) -> DMatrix<f64> {
            #bindings
            #(#temp_lets)*
            let mut m = DMatrix::zeros(DOF, DOF);
            #(#sets)*
            m
        }
    }
}

/// The emitted module's source, formatted, under `header` (as `//` lines).
///
/// # Errors
/// A message if the tokens do not parse as a Rust file (a generator bug).
pub fn emit(d: &Derivation, header: &str) -> Result<String, String> {
    format_module(model::module(d), header)
}

/// Checks `file` parses, formats it with prettyplease, puts `header` on top and turns the
/// marked doc attributes into `//` comments.
fn format_module(file: TokenStream, header: &str) -> Result<String, String> {
    let text = unsuffixed(file).to_string();
    let parsed = syn::parse_file(&text).map_err(|e| {
        // a generator bug: keep what did not parse for its report
        let dump = std::env::temp_dir().join(format!(
            "telescopic-codegen-unparsed-{}.rs",
            std::process::id()
        ));
        match std::fs::write(&dump, &text) {
            Ok(()) => format!("{e} (the unparsed tokens are in {})", dump.display()),
            Err(_) => e.to_string(),
        }
    })?;
    let body = prettyplease::unparse(&parsed);
    let mut out = String::new();
    for line in header.lines() {
        out.push_str("// ");
        out.push_str(line);
        out.push('\n');
    }
    out.push('\n');
    for line in body.lines() {
        let indent = &line[..line.len() - line.trim_start().len()];
        match line
            .trim_start()
            .strip_prefix("///")
            .and_then(|rest| rest.strip_prefix(LINE_COMMENT))
        {
            Some(text) => {
                out.push_str(indent);
                out.push_str("//");
                out.push_str(text);
            }
            None => out.push_str(line),
        }
        out.push('\n');
    }
    Ok(out)
}
