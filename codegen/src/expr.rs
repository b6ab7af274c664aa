//! Our own expression tree: plain data that leaves the Symbolica thread, with common
//! subexpression elimination, evaluation and plain-text rendering (Rust tokens: `emit`,
//! LaTeX: `render`).

use std::collections::HashMap;

/// An expression over named symbols and named numeric constants.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Expr {
    /// A rational number `num / den`.
    Rational(i64, i64),
    /// A named symbol (parameter, coordinate, intermediate).
    Symbol(String),
    /// A named high-precision constant (emitted as a correctly rounded `f64`).
    Constant(String),
    /// A sum.
    Add(Vec<Expr>),
    /// A product.
    Mul(Vec<Expr>),
    /// An integer power.
    Pow(Box<Expr>, i32),
    /// `e^x`.
    Exp(Box<Expr>),
    /// `cos x`.
    Cos(Box<Expr>),
    /// `sin x`.
    Sin(Box<Expr>),
    /// A temporary introduced by the common-subexpression pass (`t{index}`).
    Temp(usize),
}

impl Expr {
    /// True for a leaf (no subexpressions).
    fn is_leaf(&self) -> bool {
        matches!(
            self,
            Expr::Rational(..) | Expr::Symbol(_) | Expr::Constant(_) | Expr::Temp(_)
        )
    }

    fn children(&self) -> Vec<&Expr> {
        match self {
            Expr::Add(v) | Expr::Mul(v) => v.iter().collect(),
            Expr::Pow(b, _) | Expr::Exp(b) | Expr::Cos(b) | Expr::Sin(b) => vec![b],
            _ => vec![],
        }
    }

    fn map_children(&self, f: &mut impl FnMut(&Expr) -> Expr) -> Expr {
        match self {
            Expr::Add(v) => Expr::Add(v.iter().map(&mut *f).collect()),
            Expr::Mul(v) => Expr::Mul(v.iter().map(&mut *f).collect()),
            Expr::Pow(b, n) => Expr::Pow(Box::new(f(b)), *n),
            Expr::Exp(b) => Expr::Exp(Box::new(f(b))),
            Expr::Cos(b) => Expr::Cos(Box::new(f(b))),
            Expr::Sin(b) => Expr::Sin(Box::new(f(b))),
            leaf => leaf.clone(),
        }
    }

    /// Numeric value, with symbols and constants looked up by `lookup` (temporaries by
    /// `temps`).
    pub fn eval(&self, lookup: &dyn Fn(&str) -> f64, temps: &[f64]) -> f64 {
        match self {
            Expr::Rational(n, d) => *n as f64 / *d as f64,
            Expr::Symbol(s) | Expr::Constant(s) => lookup(s),
            Expr::Temp(i) => temps[*i],
            Expr::Add(v) => v.iter().map(|e| e.eval(lookup, temps)).sum(),
            Expr::Mul(v) => v.iter().map(|e| e.eval(lookup, temps)).product(),
            Expr::Pow(b, n) => b.eval(lookup, temps).powi(*n),
            Expr::Exp(b) => b.eval(lookup, temps).exp(),
            Expr::Cos(b) => b.eval(lookup, temps).cos(),
            Expr::Sin(b) => b.eval(lookup, temps).sin(),
        }
    }

    /// Plain text, e.g. `rhoA_1*l_1*K_M_1_0_0 + m_T`.
    pub fn to_text(&self) -> String {
        match self {
            Expr::Rational(n, 1) => n.to_string(),
            Expr::Rational(n, d) => format!("{n}/{d}"),
            Expr::Symbol(s) | Expr::Constant(s) => s.clone(),
            Expr::Temp(i) => format!("t{i}"),
            Expr::Add(v) => {
                let mut s = String::new();
                for (i, t) in v.iter().enumerate() {
                    let part = t.to_text();
                    if i > 0 {
                        if let Some(rest) = part.strip_prefix('-') {
                            s.push_str(" - ");
                            s.push_str(rest);
                            continue;
                        }
                        s.push_str(" + ");
                    }
                    s.push_str(&part);
                }
                s
            }
            Expr::Mul(v) => {
                let parts: Vec<String> = v
                    .iter()
                    .map(|t| {
                        if matches!(t, Expr::Add(_)) {
                            format!("({})", t.to_text())
                        } else {
                            t.to_text()
                        }
                    })
                    .collect();
                let joined = parts.join("*");
                joined.replacen("-1*", "-", 1)
            }
            Expr::Pow(b, n) => {
                let b = if b.is_leaf() {
                    b.to_text()
                } else {
                    format!("({})", b.to_text())
                };
                format!("{b}^{n}")
            }
            Expr::Exp(b) => format!("exp({})", b.to_text()),
            Expr::Cos(b) => format!("cos({})", b.to_text()),
            Expr::Sin(b) => format!("sin({})", b.to_text()),
        }
    }
}

/// Common subexpression elimination over a set of expressions: every non-leaf subtree used
/// more than once becomes a temporary. Returns the temporaries (each defined in terms of
/// earlier ones, in order of first use) and the rewritten expressions. Deterministic.
pub fn eliminate_common(exprs: &[Expr]) -> (Vec<Expr>, Vec<Expr>) {
    fn count<'a>(e: &'a Expr, counts: &mut HashMap<&'a Expr, usize>, order: &mut Vec<&'a Expr>) {
        if e.is_leaf() {
            return;
        }
        let c = counts.entry(e).or_insert(0);
        *c += 1;
        if *c > 1 {
            return; // children were counted on the first visit
        }
        for ch in e.children() {
            count(ch, counts, order);
        }
        order.push(e); // post-order: children before parents
    }
    let mut counts = HashMap::new();
    let mut order = Vec::new();
    for e in exprs {
        count(e, &mut counts, &mut order);
    }
    let shared: Vec<&Expr> = order.into_iter().filter(|e| counts[e] > 1).collect();
    let mut index: HashMap<Expr, usize> = HashMap::new();
    let mut temps = Vec::new();
    fn rewrite(e: &Expr, index: &HashMap<Expr, usize>) -> Expr {
        if let Some(&i) = index.get(e) {
            return Expr::Temp(i);
        }
        e.map_children(&mut |c| rewrite(c, index))
    }
    for s in shared {
        let def = s.map_children(&mut |c| rewrite(c, &index));
        index.insert(s.clone(), temps.len());
        temps.push(def);
    }
    let rewritten = exprs.iter().map(|e| rewrite(e, &index)).collect();
    (temps, rewritten)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sym(s: &str) -> Expr {
        Expr::Symbol(s.into())
    }

    #[test]
    fn shared_subtrees_become_temporaries_in_dependency_order() {
        let inner = Expr::Mul(vec![sym("a"), sym("b")]);
        let outer = Expr::Exp(Box::new(inner.clone()));
        let e1 = Expr::Add(vec![outer.clone(), sym("c")]);
        let e2 = Expr::Mul(vec![outer.clone(), inner.clone()]);
        let (temps, out) = eliminate_common(&[e1, e2]);
        assert_eq!(temps, vec![inner, Expr::Exp(Box::new(Expr::Temp(0)))]);
        assert_eq!(out[0], Expr::Add(vec![Expr::Temp(1), sym("c")]));
        assert_eq!(out[1], Expr::Mul(vec![Expr::Temp(1), Expr::Temp(0)]));
    }
}
