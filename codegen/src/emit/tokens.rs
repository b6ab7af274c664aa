//! Expressions as Rust tokens: literals that read back exactly, parentheses only where
//! precedence or the derivation's evaluation order needs them, the per-call symbols, and
//! the marks that become line comments after formatting.

use crate::config::ModelConfig;
use crate::expr::Expr;
use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};
use std::str::FromStr;

/// An `f64` literal that reads back to the same value (shortest round-trip form), with a
/// leading `-` when negative.
pub(super) fn float(v: f64) -> TokenStream {
    let lit = Literal::from_str(&format!("{:?}", v.abs())).expect("a float literal");
    if v.is_sign_negative() {
        quote!(-#lit)
    } else {
        quote!(#lit)
    }
}

/// How tightly emitted tokens bind, loosest first: a term of a sum needs at least
/// `Product`, a factor at least `Literal`, a method receiver `Atom`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Binding {
    Sum,
    Negated,
    Product,
    Literal,
    Atom,
}

/// Tokens and how tightly they bind.
struct Emitted {
    tokens: TokenStream,
    binding: Binding,
}

impl Emitted {
    /// The tokens, parenthesized unless they bind at least as tightly as `needed`.
    fn at_least(self, needed: Binding) -> TokenStream {
        let t = self.tokens;
        if self.binding >= needed {
            t
        } else {
            quote!((#t))
        }
    }
}

/// Splits a product's numeric factors from the rest: (negative?, remaining factors, with a
/// coefficient of magnitude 1 dropped).
fn signed_factors(factors: &[Expr]) -> (bool, Vec<Expr>) {
    let mut negative = false;
    let mut rest = Vec::with_capacity(factors.len());
    for f in factors {
        match f {
            Expr::Rational(n, d) => {
                negative ^= (*n < 0) != (*d < 0);
                if n.unsigned_abs() != d.unsigned_abs() {
                    rest.push(Expr::Rational(n.abs(), d.abs()));
                }
            }
            _ => rest.push(f.clone()),
        }
    }
    (negative, rest)
}

/// The magnitude of a sum's term and whether it is subtracted.
fn signed_term(term: &Expr) -> (bool, Expr) {
    match term {
        Expr::Rational(n, d) if (*n < 0) != (*d < 0) => (true, Expr::Rational(n.abs(), d.abs())),
        Expr::Mul(factors) => {
            let (negative, rest) = signed_factors(factors);
            let magnitude = match rest.len() {
                0 => Expr::Rational(1, 1),
                1 => rest.into_iter().next().expect("one factor"),
                _ => Expr::Mul(rest),
            };
            (negative, magnitude)
        }
        _ => (false, term.clone()),
    }
}

/// Rust tokens for an expression, with symbols resolved by `map` (unmapped symbols become
/// identifiers of the same name) and constants by their upper-case names. Parentheses only
/// where precedence needs them or where they fix the evaluation order of the derivation
/// (a nested sum or product keeps its own parentheses: floating-point `+` and `*` are not
/// associative).
pub(super) fn tokens(e: &Expr, map: &dyn Fn(&str) -> Option<TokenStream>) -> TokenStream {
    emitted(e, map).tokens
}

fn emitted(e: &Expr, map: &dyn Fn(&str) -> Option<TokenStream>) -> Emitted {
    let rec = |x: &Expr| emitted(x, map);
    let atom = |tokens| Emitted {
        tokens,
        binding: Binding::Atom,
    };
    let call = |base: &Expr, method: TokenStream| {
        let b = rec(base).at_least(Binding::Atom);
        atom(quote!(#b.#method))
    };
    match e {
        Expr::Rational(n, d) => {
            let v = *n as f64 / *d as f64;
            Emitted {
                tokens: float(v),
                binding: if v < 0.0 {
                    Binding::Negated
                } else {
                    Binding::Literal
                },
            }
        }
        Expr::Symbol(s) => atom(map(s).unwrap_or_else(|| {
            let id = format_ident!("{}", s);
            quote!(#id)
        })),
        Expr::Add(terms) => {
            let mut out = TokenStream::new();
            for (i, term) in terms.iter().enumerate() {
                let (negative, magnitude) = signed_term(term);
                let t = rec(&magnitude).at_least(Binding::Product);
                out.extend(match (i, negative) {
                    (0, false) => quote!(#t),
                    (0, true) => quote!(-#t),
                    (_, false) => quote!(+ #t),
                    (_, true) => quote!(- #t),
                });
            }
            Emitted {
                tokens: out,
                binding: Binding::Sum,
            }
        }
        Expr::Mul(factors) => {
            let (negative, rest) = signed_factors(factors);
            if !negative && rest.len() == 1 {
                return rec(&rest[0]);
            }
            let mut parts = rest.iter().map(|f| rec(f).at_least(Binding::Literal));
            let first = parts.next().unwrap_or_else(|| quote!(1.0));
            // quote's `#(..)*` cannot take `*` as a separator: join by hand
            let product = parts.fold(first, |acc, p| quote!(#acc * #p));
            if negative {
                // unary minus binds tighter than `*`; negation is exact, so `-a * b` is `-(a b)`
                Emitted {
                    tokens: quote!(-#product),
                    binding: Binding::Negated,
                }
            } else {
                Emitted {
                    tokens: product,
                    binding: Binding::Product,
                }
            }
        }
        Expr::Pow(b, n) => match *n {
            -1 => call(b, quote!(recip())),
            n => {
                let lit = Literal::i32_unsuffixed(n.abs());
                if n < 0 {
                    call(b, quote!(powi(-#lit)))
                } else {
                    call(b, quote!(powi(#lit)))
                }
            }
        },
        Expr::Exp(b) => call(b, quote!(exp())),
        Expr::Cos(b) => call(b, quote!(cos())),
        Expr::Sin(b) => call(b, quote!(sin())),
        Expr::Constant(s) => {
            let id = format_ident!("{}", s.to_uppercase());
            atom(quote!(#id))
        }
        Expr::Temp(i) => {
            let id = format_ident!("t{}", i);
            atom(quote!(#id))
        }
    }
}

/// `[i][j]`-style indices parsed from a symbol such as `k_3_4`.
fn indices(s: &str, prefix: &str) -> Option<Vec<usize>> {
    let rest = s.strip_prefix(prefix)?;
    rest.split('_').map(|p| p.parse().ok()).collect()
}

/// How the per-call code reads the derivation's symbols.
pub(super) fn call_symbol(s: &str) -> Option<TokenStream> {
    if let Some(v) = indices(s, "zd_") {
        let j = v[0];
        return Some(quote!(zd[#j]));
    }
    if let Some(v) = indices(s, "z_") {
        let j = v[0];
        return Some(quote!(z[#j]));
    }
    if let Some(v) = indices(s, "gd_") {
        let (c, j) = (v[0], v[1]);
        return Some(quote!(geo.gd[#c][#j]));
    }
    if let Some(v) = indices(s, "g_") {
        let (c, j) = (v[0], v[1]);
        return Some(quote!(geo.g[#c][#j]));
    }
    if let Some(v) = indices(s, "k_") {
        let (i, j) = (v[0], v[1]);
        return Some(quote!(self.k[#i][#j]));
    }
    if let Some(v) = indices(s, "kc_") {
        let c = v[0];
        return Some(quote!(law[#c].d_gap));
    }
    if let Some(v) = indices(s, "dc_") {
        let c = v[0];
        return Some(quote!(law[#c].d_rate));
    }
    if let Some(v) = indices(s, "f_") {
        let c = v[0];
        return Some(quote!(f[#c]));
    }
    None
}

/// `let` bindings of the parameters a matrix expression reads, by physical name.
pub(super) fn parameter_bindings(config: &ModelConfig) -> TokenStream {
    let mut out = TokenStream::new();
    for k in 0..config.sections() {
        let (rho, ei, l) = (
            format_ident!("rho_a_{}", k + 1),
            format_ident!("ei_{}", k + 1),
            format_ident!("l_{}", k + 1),
        );
        out.extend(quote! {
            let #rho = p.sections[#k].mass_per_length;
            let #ei = p.sections[#k].bending_stiffness;
            let #l = p.sections[#k].length;
        });
    }
    out.extend(quote! {
        let m_t = p.vehicle_mass;
        let m_l = p.load_mass;
        let g = p.gravity;
    });
    out
}

/// Marks a doc attribute that [`emit`] turns into a plain `//` comment after formatting
/// (quote cannot carry comments, and a doc comment on a block would be unused).
pub(super) const LINE_COMMENT: &str = "@line-comment@";

/// A `// text` line comment before the next statement (`text` starts with a space).
pub(super) fn line_comment(text: &str) -> TokenStream {
    let marked = format!("{LINE_COMMENT}{text}");
    quote!(#[doc = #marked])
}

/// Integer literals without their type suffix (`2` rather than `quote`'s `2usize`): the
/// types follow from the context in every place the module uses them.
pub(super) fn unsuffixed(tokens: TokenStream) -> TokenStream {
    use proc_macro2::{Group, TokenTree};
    tokens
        .into_iter()
        .map(|tree| match tree {
            TokenTree::Group(g) => {
                let mut inner = Group::new(g.delimiter(), unsuffixed(g.stream()));
                inner.set_span(g.span());
                TokenTree::Group(inner)
            }
            TokenTree::Literal(lit) => {
                let text = lit.to_string();
                let digits = ["usize", "i32"]
                    .iter()
                    .find_map(|suffix| text.strip_suffix(suffix))
                    .filter(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()));
                match digits {
                    Some(d) => TokenTree::Literal(Literal::from_str(d).expect("digits")),
                    None => TokenTree::Literal(lit),
                }
            }
            other => other,
        })
        .collect()
}
