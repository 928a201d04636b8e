//! The valid values of a scene key ([`Range`]): one typed value from which both the check
//! ([`Range::contains`]) and the words users read ([`Range::words`]: the schema table, the Python
//! docstrings, the docs' key tables, error messages) are made, so the two cannot drift.

use super::key_value::{Kind, Val};
use crate::error::{MAG_MAX, MAG_MIN};

/// One end of an [`Range::Interval`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bound {
    /// the end itself excluded (`<`)
    Open(f64),
    /// the end itself included (`<=`)
    Closed(f64),
}

/// The valid values of a key, for a value of the key's [`Kind`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Range {
    /// every value of the kind (names, file paths, flags)
    Any,
    /// a finite number of magnitude at most [`MAG_MAX`]
    Finite,
    /// a number from [`MAG_MIN`] to [`MAG_MAX`] (lengths, moduli, energies)
    Positive,
    /// a number between two ends, in words with the key's name (`-1 < nu < 0.5`)
    Interval { lo: Bound, hi: Bound },
    /// an integer `lo <= v` (and `v <= hi` when given)
    Int { lo: i64, hi: Option<i64> },
    /// one of these strings
    OneOf(&'static [&'static str]),
    /// 0 (with the meaning in words: "off", "= nsub") or a value of the inner range
    ZeroOr(&'static str, &'static Range),
    /// pairs and lists: at most `max` entries (None: any number), every number in `each`
    Each {
        max: Option<usize>,
        each: &'static Range,
    },
    /// empty, or a box `[x0, y0, x1, y1]` of finite numbers with x0 < x1 and y0 < y1
    BoxOrEmpty,
}

/// A number as the words show it: plain in [1e-4, 1e15), else in exponent form (1e-30, 1e30).
pub fn number(x: f64) -> String {
    if x == 0.0 || (1e-4..1e15).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

fn finite(v: f64) -> bool {
    v.is_finite() && v.abs() <= MAG_MAX
}

fn positive(v: f64) -> bool {
    v.is_finite() && (MAG_MIN..=MAG_MAX).contains(&v)
}

impl Bound {
    fn below(self, x: f64) -> bool {
        match self {
            Bound::Open(lo) => lo < x,
            Bound::Closed(lo) => lo <= x,
        }
    }
    fn above(self, x: f64) -> bool {
        match self {
            Bound::Open(hi) => x < hi,
            Bound::Closed(hi) => x <= hi,
        }
    }
    /// `lo <` or `lo <=`
    fn left(self) -> String {
        match self {
            Bound::Open(v) => format!("{} <", number(v)),
            Bound::Closed(v) => format!("{} <=", number(v)),
        }
    }
    /// `< hi` or `<= hi`
    fn right(self) -> String {
        match self {
            Bound::Open(v) => format!("< {}", number(v)),
            Bound::Closed(v) => format!("<= {}", number(v)),
        }
    }
    /// The end's value.
    pub fn value(self) -> f64 {
        match self {
            Bound::Open(v) | Bound::Closed(v) => v,
        }
    }
}

impl Range {
    /// A number of the range (a float key, or each number of a pair or a list).
    pub fn contains_f(&self, x: f64) -> bool {
        match self {
            Range::Any => true,
            Range::Finite => finite(x),
            Range::Positive => positive(x),
            Range::Interval { lo, hi } => x.is_finite() && lo.below(x) && hi.above(x),
            Range::Int { lo, hi } => {
                x.fract() == 0.0 && x >= *lo as f64 && hi.is_none_or(|h| x <= h as f64)
            }
            Range::ZeroOr(_, inner) => x == 0.0 || inner.contains_f(x),
            Range::OneOf(_) | Range::Each { .. } | Range::BoxOrEmpty => false,
        }
    }

    /// An integer of the range (an int key, or each entry of an integer list).
    pub fn contains_i(&self, x: i64) -> bool {
        match self {
            Range::Int { lo, hi } => x >= *lo && hi.is_none_or(|h| x <= h),
            Range::ZeroOr(_, inner) => x == 0 || inner.contains_i(x),
            _ => self.contains_f(x as f64),
        }
    }

    /// The check of a value of the key's kind.
    pub fn contains(&self, v: &Val) -> bool {
        let list = |n: usize, each: &dyn Fn(&Range) -> bool| match self {
            Range::Any => true,
            Range::Each { max, each: e } => max.is_none_or(|m| n <= m) && each(e),
            _ => false,
        };
        match v {
            Val::Float(x) => self.contains_f(*x),
            Val::Int(x) => self.contains_i(*x),
            Val::Str(s) => match self {
                Range::Any => true,
                Range::OneOf(opts) => opts.contains(&s.as_str()),
                _ => false,
            },
            Val::Bool(_) => matches!(self, Range::Any),
            Val::Pair(p) => list(2, &|e| p.iter().all(|&x| e.contains_f(x))),
            Val::IntList(l) => list(l.len(), &|e| l.iter().all(|&x| e.contains_i(x))),
            Val::FloatList(l) => match self {
                Range::BoxOrEmpty => {
                    let ordered = |b: &[f64]| b[0] < b[2] && b[1] < b[3];
                    l.is_empty() || (l.len() == 4 && l.iter().all(|&x| finite(x)) && ordered(l))
                }
                _ => list(l.len(), &|e| l.iter().all(|&x| e.contains_f(x))),
            },
            Val::PairList(l) => list(l.len(), &|e| {
                l.iter().all(|p| p.iter().all(|&x| e.contains_f(x)))
            }),
        }
    }

    /// The numbers of the range, in the plural (the entries of a pair or a list).
    fn plural(&self) -> String {
        match self {
            Range::Finite => format!("finite numbers with |x| <= {}", number(MAG_MAX)),
            Range::Positive => format!(
                "finite numbers in [{}, {}]",
                number(MAG_MIN),
                number(MAG_MAX)
            ),
            Range::Int { lo, hi: None } => format!("integers >= {lo}"),
            Range::Int { lo, hi: Some(h) } => format!("integers in [{lo}, {h}]"),
            Range::Interval { lo, hi } => format!("numbers x with {} x {}", lo.left(), hi.right()),
            Range::ZeroOr(zero, inner) => format!("0 ({zero}) or {}", inner.plural()),
            _ => "values".into(),
        }
    }

    /// The range in words for a key `key` of kind `kind` ("a finite number in [1e-30, 1e30]",
    /// "-1 < nu < 0.5", "an integer in [2, 5]", "one of 'free', 'clamped'").
    pub fn words(&self, kind: Kind, key: &str) -> String {
        match self {
            Range::Any => kind.phrase().into(),
            Range::Finite => format!("a finite number with |value| <= {}", number(MAG_MAX)),
            Range::Positive => format!(
                "a finite number in [{}, {}]",
                number(MAG_MIN),
                number(MAG_MAX)
            ),
            Range::Interval { lo, hi } => format!("{} {key} {}", lo.left(), hi.right()),
            Range::Int { lo, hi: None } => format!("an integer >= {lo}"),
            Range::Int { lo, hi: Some(h) } => format!("an integer in [{lo}, {h}]"),
            Range::OneOf(opts) => choice(opts),
            Range::ZeroOr(zero, inner) => format!("0 ({zero}) or {}", inner.words(kind, key)),
            Range::Each { max, each } => {
                let of = each.plural();
                let most = max.map_or(String::new(), |m| format!("at most {m} "));
                match kind {
                    Kind::Pair => format!("two {of}"),
                    Kind::PairList => format!("a list of {most}pairs of {of}"),
                    _ => format!("a list of {most}{of}"),
                }
            }
            Range::BoxOrEmpty => format!(
                "empty or a box [x0, y0, x1, y1] of finite numbers with x0 < x1 and y0 < y1 \
                 (|x| <= {})",
                number(MAG_MAX)
            ),
        }
    }

    /// The choices of a [`Range::OneOf`] (empty for the others).
    pub fn options(&self) -> &'static [&'static str] {
        match self {
            Range::OneOf(opts) => opts,
            _ => &[],
        }
    }
}

/// "one of 'a', 'b'": the words of a key whose value is one of `opts`.
pub fn choice(opts: &[&str]) -> String {
    let q: Vec<String> = opts.iter().map(|o| format!("'{o}'")).collect();
    format!("one of {}", q.join(", "))
}

impl Range {
    /// A few values of the range other than `v` (of `v`'s kind), made from the range: the
    /// values a test changes a key to.
    #[cfg(test)]
    pub(crate) fn others(&self, v: &Val) -> Vec<Val> {
        let mut ends = vec![0.0, 1.0];
        if let Range::Interval { lo, hi } = self {
            ends.push(0.5 * (lo.value() + hi.value()));
        }
        let floats = |x: f64| {
            let mut c = vec![x + 0.1, x - 0.1, 1.5 * x, 0.5 * x];
            c.extend(&ends);
            c
        };
        let cands: Vec<Val> = match v {
            Val::Float(x) => floats(*x).into_iter().map(Val::Float).collect(),
            Val::Int(i) => {
                let lo = match self {
                    Range::Int { lo, .. } => *lo,
                    _ => 0,
                };
                [i + 1, i - 1, lo, 2].into_iter().map(Val::Int).collect()
            }
            Val::Str(s) => match self {
                Range::OneOf(opts) => opts.iter().map(|o| Val::Str(o.to_string())).collect(),
                _ => vec![Val::Str(format!("{s}_2"))],
            },
            Val::Bool(b) => vec![Val::Bool(!b)],
            Val::Pair(q) => floats(q[0])
                .into_iter()
                .map(|x| Val::Pair([x, q[1]]))
                .collect(),
            Val::IntList(l) => vec![Val::IntList([l.clone(), vec![1]].concat())],
            Val::FloatList(l) if l.is_empty() => vec![Val::FloatList(vec![0.0, 0.0, 1.0, 1.0])],
            Val::FloatList(l) => {
                let mut m = l.clone();
                m[0] -= 0.1;
                vec![Val::FloatList(m)]
            }
            Val::PairList(l) if l.is_empty() => vec![Val::PairList(vec![[0.0, 0.0]; 3])],
            Val::PairList(l) => {
                let mut m = l.clone();
                m[0][0] += 0.1;
                vec![Val::PairList(m)]
            }
        };
        let mut out: Vec<Val> = Vec::new();
        for c in cands {
            if &c != v && self.contains(&c) && !out.contains(&c) {
                out.push(c);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The words and the check are made of the same ends: each end is in or out of the
    /// range as its words say.
    #[test]
    fn words_and_check_agree_at_the_ends() {
        let r = Range::Interval {
            lo: Bound::Open(-1.0),
            hi: Bound::Closed(0.5),
        };
        assert_eq!(r.words(Kind::Float, "nu"), "-1 < nu <= 0.5");
        assert!(!r.contains_f(-1.0) && r.contains_f(0.5) && !r.contains_f(f64::NAN));
        let g = Range::Int { lo: 2, hi: Some(5) };
        assert_eq!(g.words(Kind::Int, "gauss"), "an integer in [2, 5]");
        assert!(g.contains_i(5) && !g.contains_i(6) && !g.contains_i(1));
        assert_eq!(
            Range::Positive.words(Kind::Float, "E"),
            "a finite number in [1e-30, 1e30]"
        );
        let z = Range::ZeroOr("off", &Range::Positive);
        assert!(z.contains_f(0.0) && !z.contains_f(1e-31) && z.contains_f(1e-30));
        let l = Range::Each {
            max: Some(2),
            each: &Range::Int { lo: 1, hi: None },
        };
        assert!(l.contains(&Val::IntList(vec![1, 2])));
        assert!(!l.contains(&Val::IntList(vec![1, 2, 3])) && !l.contains(&Val::IntList(vec![0])));
        assert_eq!(
            l.words(Kind::IntList, "k"),
            "a list of at most 2 integers >= 1"
        );
        let b = Range::BoxOrEmpty;
        assert!(b.contains(&Val::FloatList(vec![])));
        assert!(b.contains(&Val::FloatList(vec![0.0, 0.0, 1.0, 1.0])));
        assert!(!b.contains(&Val::FloatList(vec![0.0, 1.0, 1.0, 1.0])));
    }
}
