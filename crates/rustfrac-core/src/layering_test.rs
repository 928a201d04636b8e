//! The crate's own import graph, read from `src/` at test time: no circle of files, no circle of
//! modules, and each layer imports only layers below it.
//!
//! Layers, bottom to top: `error`, then `warning`, `memory`, `geometry`; `la`; `problem` (the
//! description every driver reads); `fe`; the methods `xfem` and `pd` (neither imports the
//! other); the plate driver `fem_driver`. A file depends on another when it names an item of it:
//! a `use` (grouped trees, `self`, `super`, `crate`, renames and globs included) or a path in code
//! (`crate::a::b`, `super::x`, `module::item` through an imported module). A module's re-export
//! of its own descendants (`pub use child::Item` in a `mod.rs`) forwards a name and is no
//! dependency; every other re-export is. Names are followed through re-exports to the file that
//! defines them, so `crate::fe::Mesh` is a dependency on `fe/mesh.rs`, not on `fe/mod.rs`.

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::fs;
use std::path::Path;

/// Lexical token: comments, strings and character literals are dropped.
#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Id(String),
    /// `::`
    Sep,
    P(char),
}

/// Tokens with their 1-based line.
fn lex(src: &str) -> Vec<(Tok, usize)> {
    let c: Vec<char> = src.chars().collect();
    let (mut i, mut line, mut out) = (0, 1, Vec::new());
    let at = |i: usize| c.get(i).copied().unwrap_or('\0');
    while i < c.len() {
        let ch = c[i];
        if ch == '\n' {
            line += 1;
            i += 1;
        } else if ch.is_whitespace() {
            i += 1;
        } else if ch == '/' && at(i + 1) == '/' {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if ch == '/' && at(i + 1) == '*' {
            let mut depth = 0;
            loop {
                if i >= c.len() {
                    break;
                }
                if c[i] == '/' && at(i + 1) == '*' {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    line += usize::from(c[i] == '\n');
                    i += 1;
                }
            }
        } else if ch == '"' {
            i += 1;
            while i < c.len() && c[i] != '"' {
                line += usize::from(c[i] == '\n');
                i += if c[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
        } else if ch == '\'' {
            if at(i + 1) == '\\' {
                i += 2;
                while i < c.len() && c[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if at(i + 2) == '\'' {
                i += 3;
            } else {
                i += 1; // a lifetime
            }
        } else if ch.is_alphanumeric() || ch == '_' {
            let s = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            let word: String = c[s..i].iter().collect();
            let raw = (word == "r" || word == "br") && (at(i) == '"' || at(i) == '#');
            if raw {
                let mut hashes = 0;
                while at(i) == '#' {
                    hashes += 1;
                    i += 1;
                }
                if at(i) != '"' {
                    continue; // a raw identifier `r#name`
                }
                i += 1;
                loop {
                    if i >= c.len() {
                        break;
                    }
                    if c[i] == '"' && (1..=hashes).all(|k| at(i + k) == '#') {
                        i += 1 + hashes;
                        break;
                    }
                    line += usize::from(c[i] == '\n');
                    i += 1;
                }
            } else if !(s > 0 && word == "b" && at(i) == '\'') {
                out.push((Tok::Id(word), line));
            }
        } else if ch == ':' && at(i + 1) == ':' {
            out.push((Tok::Sep, line));
            i += 2;
        } else {
            out.push((Tok::P(ch), line));
            i += 1;
        }
    }
    out
}

/// A `use` leaf: the path as written and the name it binds (`None` for a glob).
#[derive(Clone, Debug)]
struct Use {
    /// Module path of the scope the `use` is in (an inline `mod tests` adds its name).
    ctx: Vec<String>,
    path: Vec<String>,
    bind: Option<String>,
    /// At the scope's top level (not inside a function), so visible to `super::` and re-exports.
    top: bool,
    /// Written with a visibility (`pub`, `pub(crate)`, ...).
    public: bool,
    line: usize,
}

/// A path in code (not in a `use`), resolved like a `use` path.
#[derive(Clone, Debug)]
struct Ref {
    ctx: Vec<String>,
    path: Vec<String>,
    line: usize,
}

#[derive(Debug, Default)]
struct File {
    rel: String,
    uses: Vec<Use>,
    refs: Vec<Ref>,
    /// Names this file defines (`fn`, `struct`, `enum`, `const`, ...).
    defines: BTreeSet<String>,
}

fn id(t: Option<&(Tok, usize)>) -> Option<&str> {
    match t {
        Some((Tok::Id(s), _)) => Some(s),
        _ => None,
    }
}

/// Reads one use tree from `toks[i..]` under `prefix`; returns the index after it.
/// A leaf's binding: `Some(name)`, `None` for a glob; `as _` binds nothing.
type Leaf = (Vec<String>, Option<String>);

fn use_tree(
    toks: &[(Tok, usize)],
    mut i: usize,
    prefix: Vec<String>,
    out: &mut Vec<Leaf>,
) -> usize {
    let mut path = prefix;
    loop {
        match toks.get(i).map(|t| &t.0) {
            Some(Tok::Id(s)) => {
                path.push(s.clone());
                i += 1;
                if toks.get(i).map(|t| &t.0) == Some(&Tok::Sep) {
                    i += 1;
                    continue;
                }
                let mut bind = None;
                if id(toks.get(i)) == Some("as") {
                    bind = id(toks.get(i + 1)).map(str::to_string);
                    i += 2;
                }
                if path.last().map(String::as_str) == Some("self") {
                    path.pop();
                }
                out.push((
                    path.clone(),
                    Some(bind.or_else(|| path.last().cloned()).unwrap_or_default()),
                ));
                return i;
            }
            Some(Tok::P('{')) => {
                i += 1;
                loop {
                    match toks.get(i).map(|t| &t.0) {
                        Some(Tok::P('}')) | None => return i + 1,
                        Some(Tok::P(',')) => i += 1,
                        _ => i = use_tree(toks, i, path.clone(), out),
                    }
                }
            }
            Some(Tok::P('*')) => {
                out.push((path, None));
                return i + 1;
            }
            Some(Tok::Sep) => i += 1,
            _ => return i,
        }
    }
}

const DEFINING: [&str; 9] = [
    "fn",
    "struct",
    "enum",
    "const",
    "static",
    "type",
    "trait",
    "union",
    "macro_rules",
];

fn parse(rel: &str, module: &[String], src: &str) -> File {
    let toks = lex(src);
    let mut f = File {
        rel: rel.to_string(),
        ..File::default()
    };
    let mut depth = 0usize;
    // Inline modules: (brace depth inside them, name).
    let mut inline: Vec<(usize, String)> = Vec::new();
    let ctx_of = |inline: &[(usize, String)]| {
        let mut c = module.to_vec();
        c.extend(inline.iter().map(|(_, n)| n.clone()));
        c
    };
    let mut i = 0;
    while i < toks.len() {
        let (t, line) = (&toks[i].0, toks[i].1);
        match t {
            Tok::P('{') => depth += 1,
            Tok::P('}') => {
                if inline.last().map(|x| x.0) == Some(depth) {
                    inline.pop();
                }
                depth = depth.saturating_sub(1);
            }
            Tok::Id(w) if w == "mod" => {
                if let (Some(name), Some((Tok::P('{'), _))) = (id(toks.get(i + 1)), toks.get(i + 2))
                {
                    inline.push((depth + 1, name.to_string()));
                    depth += 1;
                    i += 3;
                    continue;
                }
            }
            Tok::Id(w) if DEFINING.contains(&w.as_str()) => {
                let k = if w == "macro_rules" { i + 2 } else { i + 1 };
                if let Some(name) = id(toks.get(k)) {
                    f.defines.insert(name.to_string());
                }
            }
            Tok::Id(w) if w == "use" => {
                let public = i > 0
                    && (id(toks.get(i - 1)) == Some("pub")
                        || toks.get(i - 1).map(|t| &t.0) == Some(&Tok::P(')')));
                let mut leaves = Vec::new();
                let end = use_tree(&toks, i + 1, Vec::new(), &mut leaves);
                let top = depth == inline.last().map_or(0, |x| x.0);
                for (path, bind) in leaves {
                    f.uses.push(Use {
                        ctx: ctx_of(&inline),
                        path,
                        bind,
                        top,
                        public,
                        line,
                    });
                }
                i = end;
                continue;
            }
            Tok::Id(w) if toks.get(i + 1).map(|t| &t.0) == Some(&Tok::Sep) => {
                let after_sep = i > 0 && toks[i - 1].0 == Tok::Sep;
                // `pub(in crate::a)` names a visibility, not an item.
                let visibility =
                    i > 1 && id(toks.get(i - 1)) == Some("in") && toks[i - 2].0 == Tok::P('(');
                if !after_sep && !visibility && w != "Self" {
                    let mut path = vec![w.clone()];
                    let mut k = i + 1;
                    while toks.get(k).map(|t| &t.0) == Some(&Tok::Sep) {
                        match id(toks.get(k + 1)) {
                            Some(s) => path.push(s.to_string()),
                            None => break,
                        }
                        k += 2;
                    }
                    f.refs.push(Ref {
                        ctx: ctx_of(&inline),
                        path,
                        line,
                    });
                    i = k;
                    continue;
                }
            }
            _ => {}
        }
        i += 1;
    }
    f
}

/// What a path names: a module, or an item of the file that defines it.
#[derive(Clone, Debug, PartialEq)]
enum Target {
    Module(Vec<String>),
    Item(String),
}

struct Crate {
    /// Module path -> file.
    files: BTreeMap<Vec<String>, File>,
}

impl Crate {
    fn read(src: &Path) -> Crate {
        let mut files = BTreeMap::new();
        let mut stack = vec![src.to_path_buf()];
        while let Some(dir) = stack.pop() {
            for e in fs::read_dir(&dir).unwrap() {
                let p = e.unwrap().path();
                if p.is_dir() {
                    stack.push(p);
                    continue;
                }
                if p.extension().and_then(|x| x.to_str()) != Some("rs") {
                    continue;
                }
                let rel = p
                    .strip_prefix(src)
                    .unwrap()
                    .to_string_lossy()
                    .replace('\\', "/");
                let mut module: Vec<String> = rel
                    .trim_end_matches(".rs")
                    .split('/')
                    .map(str::to_string)
                    .collect();
                if matches!(module.last().map(String::as_str), Some("mod" | "lib")) {
                    module.pop();
                }
                let text = fs::read_to_string(&p).unwrap();
                files.insert(module.clone(), parse(&rel, &module, &text));
            }
        }
        Crate { files }
    }

    /// The file-backed module holding `ctx` (inline modules live in their file).
    fn owner(&self, ctx: &[String]) -> Vec<String> {
        let mut m = ctx.to_vec();
        while !self.files.contains_key(&m) && !m.is_empty() {
            m.pop();
        }
        m
    }

    fn file_of(&self, t: &Target) -> String {
        match t {
            Target::Item(f) => f.clone(),
            Target::Module(m) => self.files[&self.owner(m)].rel.clone(),
        }
    }

    fn is_module(&self, m: &[String]) -> bool {
        self.files.contains_key(m)
    }

    /// The uses visible in scope `ctx` (top level of that module).
    fn scope_uses<'a>(&'a self, ctx: &'a [String]) -> impl Iterator<Item = &'a Use> {
        self.files[&self.owner(ctx)]
            .uses
            .iter()
            .filter(move |u| u.ctx == ctx && u.top)
    }

    /// One name looked up in module `m`.
    fn step(&self, m: &[String], name: &str, fuel: usize) -> Option<Target> {
        if fuel == 0 {
            return None;
        }
        let mut child = m.to_vec();
        child.push(name.to_string());
        if self.is_module(&child) {
            return Some(Target::Module(child));
        }
        if let Some(u) = self.scope_uses(m).find(|u| u.bind.as_deref() == Some(name)) {
            return self.resolve(m, &u.path, fuel - 1);
        }
        let file = &self.files[&self.owner(m)];
        if !file.defines.contains(name) {
            for u in self.scope_uses(m).filter(|u| u.bind.is_none()) {
                if let Some(Target::Module(g)) = self.resolve(m, &u.path, fuel - 1) {
                    if self.has(&g, name) {
                        return self.step(&g, name, fuel - 1);
                    }
                }
            }
        }
        Some(Target::Item(file.rel.clone()))
    }

    fn has(&self, m: &[String], name: &str) -> bool {
        let mut child = m.to_vec();
        child.push(name.to_string());
        self.is_module(&child)
            || self.files[&self.owner(m)].defines.contains(name)
            || self.scope_uses(m).any(|u| u.bind.as_deref() == Some(name))
    }

    /// Resolves `path` written in scope `ctx`; `None` for another crate's path.
    fn resolve(&self, ctx: &[String], path: &[String], fuel: usize) -> Option<Target> {
        if fuel == 0 || path.is_empty() {
            return None;
        }
        let (mut cur, rest) = match path[0].as_str() {
            "crate" => (Target::Module(Vec::new()), &path[1..]),
            "self" => (Target::Module(ctx.to_vec()), &path[1..]),
            "super" => {
                let n = path.iter().take_while(|s| *s == "super").count();
                let m = ctx[..ctx.len().saturating_sub(n)].to_vec();
                (Target::Module(m), &path[n..])
            }
            first => {
                let mut child = ctx.to_vec();
                child.push(first.to_string());
                let start = if self.is_module(&child) {
                    Target::Module(child)
                } else {
                    let f = &self.files[&self.owner(ctx)];
                    let u = f
                        .uses
                        .iter()
                        .find(|u| u.ctx == ctx && u.bind.as_deref() == Some(first))?;
                    self.resolve(&u.ctx, &u.path, fuel - 1)?
                };
                (start, &path[1..])
            }
        };
        for seg in rest {
            cur = match cur {
                Target::Item(_) => return Some(cur),
                Target::Module(m) => self.step(&m, seg, fuel - 1)?,
            };
        }
        Some(cur)
    }

    /// File dependencies: (from, to) -> the lines that make them.
    fn edges(&self) -> BTreeMap<(String, String), Vec<String>> {
        let mut out: BTreeMap<(String, String), Vec<String>> = BTreeMap::new();
        for (module, f) in &self.files {
            let mut add = |t: Option<Target>, line: usize, path: &[String]| {
                let Some(t) = t else { return };
                let to = self.file_of(&t);
                if to != f.rel {
                    out.entry((f.rel.clone(), to)).or_default().push(format!(
                        "{}:{line} {}",
                        f.rel,
                        path.join("::")
                    ));
                }
            };
            for u in &f.uses {
                let t = self.resolve(&u.ctx, &u.path, 64);
                let forwards = u.public
                    && matches!(&t, Some(t) if self.module_of_file(&self.file_of(t)).starts_with(module) );
                if !forwards {
                    add(t, u.line, &u.path);
                }
            }
            for r in &f.refs {
                add(self.resolve(&r.ctx, &r.path, 64), r.line, &r.path);
            }
        }
        out
    }

    fn module_of_file(&self, rel: &str) -> Vec<String> {
        self.files
            .iter()
            .find(|(_, f)| f.rel == rel)
            .map(|(m, _)| m.clone())
            .unwrap_or_default()
    }
}

/// The strongly connected components with more than one member, each as a shortest circle
/// through its first member and its sorted members.
fn circles(
    nodes: &BTreeSet<String>,
    adj: &BTreeMap<String, BTreeSet<String>>,
) -> Vec<(Vec<String>, Vec<String>)> {
    let reach = |from: &String| {
        let mut seen = BTreeSet::new();
        let mut stack = vec![from.clone()];
        while let Some(n) = stack.pop() {
            for m in adj.get(&n).into_iter().flatten() {
                if seen.insert(m.clone()) {
                    stack.push(m.clone());
                }
            }
        }
        seen
    };
    let reach: BTreeMap<&String, BTreeSet<String>> = nodes.iter().map(|n| (n, reach(n))).collect();
    let mut done = BTreeSet::new();
    let mut out = Vec::new();
    for n in nodes {
        if done.contains(n) || !reach[n].contains(n) {
            continue;
        }
        let scc: BTreeSet<String> = reach[n]
            .iter()
            .filter(|m| reach[*m].contains(n))
            .cloned()
            .collect();
        done.extend(scc.iter().cloned());
        // breadth first from n inside the component, back to n
        let mut prev: BTreeMap<String, String> = BTreeMap::new();
        let mut last = None;
        let mut queue = VecDeque::from([n.clone()]);
        'bfs: while let Some(a) = queue.pop_front() {
            for b in adj
                .get(&a)
                .into_iter()
                .flatten()
                .filter(|b| scc.contains(*b))
            {
                if b == n {
                    last = Some(a.clone());
                    break 'bfs;
                }
                if !prev.contains_key(b) {
                    prev.insert(b.clone(), a.clone());
                    queue.push_back(b.clone());
                }
            }
        }
        let mut path = vec![n.clone()];
        let mut cur = last.expect("n reaches itself inside its component");
        while &cur != n {
            path.push(cur.clone());
            cur = prev[&cur].clone();
        }
        path.push(n.clone());
        path.reverse();
        out.push((path, scc.into_iter().collect()));
    }
    out
}

/// The layer of a top-level module; a file may import only its own module and lower layers.
fn layer(top: &str) -> Option<usize> {
    Some(match top {
        "lib.rs" | "layering_test" => return None,
        "error" => 0,
        "warning" | "memory" | "geometry" => 1,
        "la" => 2,
        "problem" => 3,
        "fe" => 4,
        "xfem" | "pd" => 5,
        "fem_driver" => 6,
        "output" => 7,
        other => panic!("the top-level module {other} has no layer: give it one here"),
    })
}

fn top_module(rel: &str) -> &str {
    let first = rel.split('/').next().unwrap();
    first.strip_suffix(".rs").unwrap_or(first)
}

/// The module path of a file (`pd/sla/driver.rs` -> `pd::sla::driver`, `pd/mod.rs` -> `pd`).
fn module_path(rel: &str) -> Vec<&str> {
    let mut m: Vec<&str> = rel.trim_end_matches(".rs").split('/').collect();
    if matches!(m.last(), Some(&"mod" | &"lib")) {
        m.pop();
    }
    m
}

/// An edge between files as one between sibling modules: the children of the deepest module
/// holding both (`pd/splice/build.rs -> pd/sla/driver.rs` is `pd::splice -> pd::sla`). None
/// between a module and its own descendants (the file graph sees those).
fn siblings(a: &str, b: &str) -> Option<(String, String)> {
    let (ma, mb) = (module_path(a), module_path(b));
    let k = ma.iter().zip(&mb).take_while(|(x, y)| x == y).count();
    (k < ma.len() && k < mb.len()).then(|| (ma[..=k].join("::"), mb[..=k].join("::")))
}

fn graph() -> BTreeMap<(String, String), Vec<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    Crate::read(&src).edges()
}

/// The circles of a graph given by its edges, each with the lines that make its hops; the
/// components equal to one of `known` (sorted member lists) are left out, and each of `known`
/// not found is reported as gone.
fn report(
    kind: &str,
    edges: &BTreeMap<(String, String), Vec<String>>,
    known: &[&[&str]],
) -> Vec<String> {
    let mut nodes = BTreeSet::new();
    let mut adj: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (a, b) in edges.keys() {
        nodes.insert(a.clone());
        nodes.insert(b.clone());
        adj.entry(a.clone()).or_default().insert(b.clone());
    }
    let mut seen = Vec::new();
    let mut out: Vec<String> = circles(&nodes, &adj)
        .into_iter()
        .filter_map(|(path, members)| {
            seen.push(members.clone());
            if known
                .iter()
                .any(|k| k.iter().copied().eq(members.iter().map(String::as_str)))
            {
                return None;
            }
            let hops: Vec<String> = path
                .windows(2)
                .map(|w| {
                    format!(
                        "    {} -> {}  ({})",
                        w[0],
                        w[1],
                        edges[&(w[0].clone(), w[1].clone())][0]
                    )
                })
                .collect();
            Some(format!(
                "a circle of {kind}: {}\n{}\n    (all of its {}: {})",
                path.join(" -> "),
                hops.join("\n"),
                kind,
                members.join(", ")
            ))
        })
        .collect();
    for k in known {
        if !seen
            .iter()
            .any(|m| k.iter().copied().eq(m.iter().map(String::as_str)))
        {
            out.push(format!(
                "the known circle of {kind} {k:?} is gone: remove it from the list"
            ));
        }
    }
    out
}

/// Circles of files known today (each component's members, sorted), tolerated until split; a
/// new circle, or one of these growing, fails (none today).
const KNOWN_FILE_CIRCLES: &[&[&str]] = &[];

/// Circles of sibling modules known today (each component's members, sorted); a new circle fails
/// (none today).
const KNOWN_MODULE_CIRCLES: &[&[&str]] = &[];

#[test]
fn no_circle_of_files() {
    let found = report("files", &graph(), KNOWN_FILE_CIRCLES);
    assert!(found.is_empty(), "\n{}\n", found.join("\n"));
}

#[test]
fn no_circle_of_modules() {
    let mut lifted: BTreeMap<(String, String), Vec<String>> = BTreeMap::new();
    for ((a, b), lines) in graph() {
        if let Some(e) = siblings(&a, &b) {
            lifted.entry(e).or_default().extend(lines);
        }
    }
    let found = report("modules", &lifted, KNOWN_MODULE_CIRCLES);
    assert!(found.is_empty(), "\n{}\n", found.join("\n"));
}

#[test]
fn each_layer_imports_only_layers_below() {
    let edges = graph();
    let mut bad = Vec::new();
    for ((a, b), lines) in &edges {
        let (ta, tb) = (top_module(a), top_module(b));
        let (Some(la), Some(lb)) = (layer(ta), layer(tb)) else {
            continue;
        };
        if ta != tb && lb >= la {
            bad.push(format!(
                "{ta} (layer {la}) imports {tb} (layer {lb}): {}",
                lines[0]
            ));
        }
    }
    assert!(bad.is_empty(), "\n{}\n", bad.join("\n"));
}

/// The reader itself, on a small crate written for it: it must see the edges it is meant to see
/// and the circle there is, or the tests above pass vacuously.
#[test]
fn the_reader_resolves_uses_and_paths() {
    let dir = std::env::temp_dir().join(format!("rustfrac-layering-{}", std::process::id()));
    let files: [(&str, &str); 6] = [
        ("lib.rs", "mod a;\nmod b;\nmod c;\nmod m;\npub use a::A;\n"),
        ("a.rs", "use crate::m::{self, Inner as In};\npub struct A;\nfn f() { crate::b::g() }\n"),
        ("b.rs", "pub fn g() {}\n#[cfg(test)]\nmod tests {\n    use super::*;\n    use crate::A;\n}\n"),
        ("c.rs", "// crate::b::g\nconst S: &str = \"crate::b::g\";\nconst C: char = '\"';\n/* super::b */\n"),
        ("m/mod.rs", "mod inner;\npub use inner::Inner;\npub(in crate::m) fn h() {}\n"),
        ("m/inner.rs", "pub struct Inner;\nfn k() { super::super::b::g() }\n"),
    ];
    fs::create_dir_all(dir.join("m")).unwrap();
    for (name, text) in files {
        fs::write(dir.join(name), text).unwrap();
    }
    let edges = Crate::read(&dir).edges();
    fs::remove_dir_all(&dir).unwrap();
    let got: Vec<String> = edges.keys().map(|(a, b)| format!("{a} -> {b}")).collect();
    // through a renaming group to the defining file, a module itself, a path in code, a test's
    // import through the crate root's re-export, a `super::super` path; nothing from comments,
    // strings or a visibility, and the module forwarding its child's item depends on nothing
    assert_eq!(
        got,
        [
            "a.rs -> b.rs",
            "a.rs -> m/inner.rs",
            "a.rs -> m/mod.rs",
            "b.rs -> a.rs",
            "m/inner.rs -> b.rs"
        ]
    );
    let found = report("files", &edges, &[]);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(
        found[0].starts_with("a circle of files: a.rs -> b.rs -> a.rs"),
        "{}",
        found[0]
    );
    let gone = report("files", &BTreeMap::new(), &[&["a.rs", "b.rs"]]);
    assert!(gone[0].contains("is gone"), "{gone:?}");

    // and on this crate: re-exports followed to the defining file
    let edges = graph();
    let files: BTreeSet<&String> = edges.keys().map(|(a, _)| a).collect();
    assert!(files.len() > 50, "read only {} files", files.len());
    let has = |a: &str, b: &str| edges.contains_key(&(a.to_string(), b.to_string()));
    assert!(has("la/cholesky.rs", "la/csc.rs") && has("fe/model.rs", "la/csc.rs"));
    assert!(!has("la/mod.rs", "la/csc.rs"));
}
