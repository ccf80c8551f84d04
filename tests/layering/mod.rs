//! Each crate's module import graph, read from its source, and the import circles in it.
//!
//! Shared by the workspace's `tests/layers.rs` (every crate under `crates/*/src`) and
//! `crates/pelt-preview/tests/layers.rs` (the renderer's core/feature rule), which includes
//! this file by `#[path]`.
//!
//! **What a module is.** Every `.rs` file under a crate's `src/` is one module, found by
//! walking every subfolder: `lib.rs` (or `main.rs`) is the crate root, `a.rs` and `a/mod.rs`
//! are `a`, `a/b.rs` is `a::b`. Each file under `src/bin/` (or `src/bin/x/main.rs` with its
//! folder) is the root of a crate of its own. An inline `mod x { … }` is a scope of its own
//! for resolving paths (its `super` is the file's module) but belongs to its file's node in
//! the graph: a file is the unit that imports and is imported.
//!
//! **What is read.** Comments (doc comments, and with them doc links, included) and the
//! contents of string and character literals are removed; so is every item under
//! `#[cfg(test)]` (a `#[cfg(test)] mod x;` drops the file of `x` too). What is left is read as
//! tokens: every `use` tree (brace groups nested to any depth, `self`, `as`, globs) and every
//! other path that starts with `crate`, `$crate`, `super` or `self`, or with the name of a
//! child module of the scope it is written in (2018 paths: `use child::X`, `child::f()`).
//! Paths that start with anything else name other crates or names brought in by a `use`,
//! which is read on its own.
//!
//! **Where a path leads (the rule).** A path is followed module by module as long as its
//! segments name modules; the first segment that is not a module names an item. If the
//! module reached brings that name in with a `use` of its own (a re-export such as the crate
//! root's `pub use scene::Scene`, or a glob `pub use scene::*` whose module defines or binds
//! the name), the path is followed on through that `use`, so it leads to the module that
//! owns the item, not to the module that re-exports it. Otherwise the item is the reached
//! module's own. An edge joins the importing file's module to the file module the path leads
//! to (none to itself). A re-export is therefore an import of the module re-exporting (the
//! crate root's `pub use scene::Scene` is an edge root → `scene`), but naming the item
//! through it is an import of its owner, not of the root: `use crate::Scene` in `fur` is the
//! edge `fur` → `scene`.

#![expect(
    dead_code,
    reason = "each includer uses its part: the workspace test the walk and the circles, \
              pelt-preview's one crate's graph"
)]

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// One crate's modules, by path (`lib` for the root, `a`, `a::b`; inline scopes `a::b::c`).
#[derive(Debug, Default)]
pub struct Crate {
    /// The crate's name (the folder's, and `folder/bin/name` for a binary under `src/bin/`).
    pub name: String,
    /// The root module's key (`lib`, `main` or the binary's name).
    pub root: String,
    /// Every scope: file modules and inline modules.
    pub scopes: BTreeMap<String, Scope>,
}

/// A module scope: a file's module or an inline `mod x { … }` in one.
#[derive(Debug, Default)]
pub struct Scope {
    /// The file module this scope belongs to (itself for a file).
    pub file_module: String,
    /// The file it was read from (relative to `src/`).
    pub file: PathBuf,
    /// The enclosing scope (`None` for the root).
    pub parent: Option<String>,
    /// Child modules by name (files and inline modules).
    pub children: BTreeSet<String>,
    /// What its `use` trees bring in.
    pub uses: Vec<UseItem>,
    /// The names of the items it defines (`struct`, `fn`, `mod`, …).
    pub items: BTreeSet<String>,
    /// Every path it writes that may name a module of this crate (its `use` items included).
    pub paths: Vec<Vec<String>>,
}

/// One leaf of a `use` tree.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UseItem {
    /// The full path, groups expanded (`use a::{b::{C}}` → `a::b::C`); `self` leaves dropped.
    pub path: Vec<String>,
    /// The name it binds (`None` for a glob or `as _`).
    pub name: Option<String>,
    /// Whether it is a glob (`a::*`).
    pub glob: bool,
}

/// The modules each file module imports, each with the paths that made the edge.
pub type Graph = BTreeMap<String, BTreeMap<String, BTreeSet<String>>>;

/// Every crate under `<workspace>/crates/*/src`, with the binaries under `src/bin/` as crates
/// of their own.
pub fn workspace_crates(workspace: &Path) -> Vec<Crate> {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(workspace.join("crates"))
        .expect("crates/")
        .map(|e| e.expect("entry").path().join("src"))
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    let mut out = Vec::new();
    for src in dirs {
        let name = src
            .parent()
            .and_then(Path::file_name)
            .and_then(|n| n.to_str())
            .expect("crate folder")
            .to_owned();
        let mut files = Vec::new();
        read_tree(&src, &src, &mut files);
        let (bins, lib): (Vec<_>, Vec<_>) =
            files.into_iter().partition(|(p, _)| p.starts_with("bin"));
        if !lib.is_empty() {
            out.push(crate_from_sources(&name, &lib));
        }
        let mut by_bin: BTreeMap<String, Vec<(PathBuf, String)>> = BTreeMap::new();
        for (p, text) in bins {
            let rel = p.strip_prefix("bin").expect("bin/").to_path_buf();
            let mut parts = rel.iter().map(|s| s.to_string_lossy().into_owned());
            let first = parts.next().expect("bin file");
            let bin = first.trim_end_matches(".rs").to_owned();
            // `bin/x.rs` is the root `main.rs` of `x`; `bin/x/…` are its files.
            let inner = if rel.components().count() == 1 {
                PathBuf::from("main.rs")
            } else {
                rel.strip_prefix(&first).expect("bin folder").to_path_buf()
            };
            by_bin.entry(bin).or_default().push((inner, text));
        }
        for (bin, files) in by_bin {
            out.push(crate_from_sources(&format!("{name}/bin/{bin}"), &files));
        }
    }
    out
}

/// The crate whose `src/` folder is `src` (its binaries under `src/bin/` left out).
pub fn crate_from_dir(name: &str, src: &Path) -> Crate {
    let mut files = Vec::new();
    read_tree(src, src, &mut files);
    files.retain(|(p, _)| !p.starts_with("bin"));
    crate_from_sources(name, &files)
}

/// Every `.rs` file under `dir`, relative to `base`, with its text.
fn read_tree(base: &Path, dir: &Path, out: &mut Vec<(PathBuf, String)>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("source folder")
        .map(|e| e.expect("entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            read_tree(base, &path, out);
        } else if path.extension().is_some_and(|x| x == "rs") {
            let text = std::fs::read_to_string(&path).expect("read source");
            let rel = path.strip_prefix(base).expect("under src").to_path_buf();
            out.push((rel, text));
        }
    }
}

/// The module path of a file relative to `src/` (`lib.rs` → the root, `a/mod.rs` → `a`).
fn module_of(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel
        .iter()
        .map(|s| s.to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().expect("a file name");
    let stem = last.trim_end_matches(".rs");
    if !(parts.is_empty() && (stem == "lib" || stem == "main")) && stem != "mod" {
        parts.push(stem.to_owned());
    }
    parts
}

/// A crate read from `(path relative to src/, text)` pairs; a crate with `lib.rs` or
/// `main.rs` at the top. Synthetic sources (the negative controls) come in this way.
pub fn crate_from_sources(name: &str, files: &[(PathBuf, String)]) -> Crate {
    let root = if files.iter().any(|(p, _)| p == Path::new("lib.rs")) {
        "lib"
    } else {
        "main"
    };
    let mut krate = Crate {
        name: name.to_owned(),
        root: root.to_owned(),
        scopes: BTreeMap::new(),
    };
    // Strip every file first: a `#[cfg(test)] mod x;` removes x's file.
    let mut stripped = Vec::new();
    let mut test_only: BTreeSet<Vec<String>> = BTreeSet::new();
    for (rel, text) in files {
        let module = module_of(rel);
        let (code, test_mods) = strip(text);
        for m in test_mods {
            let mut p = module.clone();
            p.push(m);
            test_only.insert(p);
        }
        stripped.push((rel.clone(), module, code));
    }
    stripped.retain(|(_, m, _)| !test_only.iter().any(|t| m.starts_with(t)));
    for (rel, module, _) in &stripped {
        // Every file module and its ancestors exist, and each parent knows the child.
        for n in 0..=module.len() {
            let key = krate.key(&module[..n]);
            let parent = (n > 0).then(|| krate.key(&module[..n - 1]));
            let scope = krate.scopes.entry(key.clone()).or_default();
            scope.file_module.clone_from(&key);
            scope.parent = parent.clone();
            if n == module.len() {
                scope.file.clone_from(rel);
            }
            if let Some(p) = parent {
                let child = module[n - 1].clone();
                krate.scopes.entry(p).or_default().children.insert(child);
            }
        }
    }
    for (_, module, code) in &stripped {
        let key = krate.key(module);
        read_scope(&mut krate, &key, &tokens(code));
    }
    krate
}

impl Crate {
    /// The key of a module path (the root's for an empty one).
    fn key(&self, module: &[String]) -> String {
        if module.is_empty() {
            self.root.clone()
        } else {
            module.join("::")
        }
    }

    /// The key of `name` under `parent`.
    fn child_key(&self, parent: &str, name: &str) -> String {
        if parent == self.root {
            name.to_owned()
        } else {
            format!("{parent}::{name}")
        }
    }

    /// The file modules (the graph's nodes).
    pub fn file_modules(&self) -> BTreeSet<String> {
        self.scopes
            .values()
            .map(|s| s.file_module.clone())
            .collect()
    }

    /// The module a path written in `from` leads to, by the rule in this file's docs;
    /// `None` for a path into another crate.
    pub fn resolve(&self, from: &str, path: &[String]) -> Option<String> {
        self.resolve_depth(from, path, 0)
    }

    /// [`Crate::resolve`], following at most a bounded chain of re-exports.
    fn resolve_depth(&self, from: &str, path: &[String], depth: usize) -> Option<String> {
        if depth > 16 {
            return Some(from.to_owned());
        }
        let first = path.first()?;
        let mut at = match first.as_str() {
            "crate" | "$crate" => self.root.clone(),
            "self" => from.to_owned(),
            "super" => self.scopes.get(from)?.parent.clone()?,
            name if self.scopes.get(from)?.children.contains(name) => self.child_key(from, name),
            name => {
                // A name a `use` of this scope brought in (`use crate::fur;` … `fur::X`).
                let u = self
                    .scopes
                    .get(from)?
                    .uses
                    .iter()
                    .find(|u| !u.glob && u.name.as_deref() == Some(name) && u.path.len() > 1)?;
                let mut p = u.path.clone();
                p.extend_from_slice(&path[1..]);
                return self.resolve_depth(from, &p, depth + 1);
            }
        };
        let mut rest = &path[1..];
        while let Some(seg) = rest.first() {
            let scope = self.scopes.get(&at)?;
            if seg == "super" {
                at = scope.parent.clone()?;
            } else if seg == "self" {
                // `a::{self}`: the module itself.
            } else if scope.children.contains(seg) {
                at = self.child_key(&at, seg);
            } else {
                return self.through_use(&at, seg, &rest[1..], depth);
            }
            rest = &rest[1..];
        }
        Some(at)
    }

    /// Where the item `name` of module `at` leads: through the `use` that brings it in, if
    /// one does (`None` when that `use` leads into another crate), else to `at` itself.
    fn through_use(&self, at: &str, name: &str, rest: &[String], depth: usize) -> Option<String> {
        let scope = &self.scopes[at];
        if scope.items.contains(name) {
            return Some(at.to_owned());
        }
        if let Some(u) = scope
            .uses
            .iter()
            .find(|u| !u.glob && u.name.as_deref() == Some(name))
        {
            // `use a::X as Y`: the path goes on from `a::X`.
            let mut p = u.path.clone();
            p.extend_from_slice(rest);
            return self.resolve_depth(at, &p, depth + 1);
        }
        for u in scope.uses.iter().filter(|u| u.glob) {
            if let Some(g) = self.resolve_depth(at, &u.path, depth + 1)
                && self.scopes.get(&g).is_some_and(|s| s.binds(name))
            {
                let mut p = u.path.clone();
                p.push(name.to_owned());
                p.extend_from_slice(rest);
                return self.resolve_depth(at, &p, depth + 1);
            }
        }
        Some(at.to_owned())
    }

    /// Each file module's imports: the module each of its paths leads to, with the paths.
    pub fn graph(&self) -> Graph {
        let mut out: Graph = BTreeMap::new();
        for m in self.file_modules() {
            out.entry(m).or_default();
        }
        for (key, scope) in &self.scopes {
            for path in &scope.paths {
                let Some(to) = self.resolve(key, path) else {
                    continue;
                };
                let to = self
                    .scopes
                    .get(&to)
                    .map_or(to.clone(), |s| s.file_module.clone());
                if to != scope.file_module {
                    out.entry(scope.file_module.clone())
                        .or_default()
                        .entry(to)
                        .or_default()
                        .insert(path.join("::"));
                }
            }
        }
        out
    }
}

impl Scope {
    /// Whether the scope defines, declares or imports `name`.
    fn binds(&self, name: &str) -> bool {
        self.items.contains(name)
            || self.children.contains(name)
            || self.uses.iter().any(|u| u.name.as_deref() == Some(name))
    }
}

/// The strongly connected components of more than one module (Tarjan's algorithm), each
/// sorted, in the order of their first module.
pub fn circles(graph: &Graph) -> Vec<BTreeSet<String>> {
    /// Tarjan's state.
    struct State<'g> {
        graph: &'g Graph,
        index: BTreeMap<&'g str, usize>,
        low: BTreeMap<&'g str, usize>,
        stack: Vec<&'g str>,
        on_stack: BTreeSet<&'g str>,
        out: Vec<BTreeSet<String>>,
    }
    /// Visits `v` and what it reaches.
    fn visit<'g>(s: &mut State<'g>, v: &'g str) {
        let i = s.index.len();
        s.index.insert(v, i);
        s.low.insert(v, i);
        s.stack.push(v);
        s.on_stack.insert(v);
        for w in s.graph.get(v).into_iter().flat_map(BTreeMap::keys) {
            let w = w.as_str();
            if !s.index.contains_key(w) {
                visit(s, w);
                let lw = s.low[w];
                let lv = s.low[v];
                s.low.insert(v, lv.min(lw));
            } else if s.on_stack.contains(w) {
                let iw = s.index[w];
                let lv = s.low[v];
                s.low.insert(v, lv.min(iw));
            }
        }
        if s.low[v] == s.index[v] {
            let mut comp = BTreeSet::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack.remove(w);
                comp.insert(w.to_owned());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                s.out.push(comp);
            }
        }
    }
    let mut s = State {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in graph.keys() {
        if !s.index.contains_key(v.as_str()) {
            visit(&mut s, v);
        }
    }
    s.out.sort();
    s.out
}

/// A circle written out with the edges inside it and the paths behind each.
pub fn describe(graph: &Graph, circle: &BTreeSet<String>) -> String {
    let mut out = format!(
        "{{{}}}",
        circle.iter().cloned().collect::<Vec<_>>().join(", ")
    );
    for from in circle {
        for (to, paths) in &graph[from] {
            if circle.contains(to) {
                let paths: Vec<&str> = paths.iter().map(String::as_str).collect();
                out.push_str(&format!("\n      {from} -> {to}: {}", paths.join(", ")));
            }
        }
    }
    out
}

/// `text` with comments, literal contents and `#[cfg(test)]` items removed, and the names of
/// the `#[cfg(test)] mod x;` declarations it had.
pub fn strip(text: &str) -> (String, Vec<String>) {
    let code = strip_comments(text);
    strip_test_items(&code)
}

/// `text` without comments (line, block, nested, doc) and with empty string and character
/// literals; lifetimes kept.
fn strip_comments(text: &str) -> String {
    let c: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    let ident = |ch: char| ch.is_alphanumeric() || ch == '_';
    while i < c.len() {
        let next = c.get(i + 1).copied();
        match c[i] {
            '/' if next == Some('/') => {
                while i < c.len() && c[i] != '\n' {
                    i += 1;
                }
            }
            '/' if next == Some('*') => {
                let mut depth = 0;
                while i < c.len() {
                    if c[i] == '/' && c.get(i + 1) == Some(&'*') {
                        depth += 1;
                        i += 2;
                    } else if c[i] == '*' && c.get(i + 1) == Some(&'/') {
                        depth -= 1;
                        i += 2;
                        if depth == 0 {
                            break;
                        }
                    } else {
                        i += 1;
                    }
                }
                out.push(' ');
            }
            'r' if (i == 0
                || !ident(c[i - 1])
                || (c[i - 1] == 'b' && (i < 2 || !ident(c[i - 2]))))
                && matches!(next, Some('"' | '#'))
                && raw_string_end(&c, i + 1).is_some() =>
            {
                i = raw_string_end(&c, i + 1).unwrap_or(c.len());
                out.push_str("\"\"");
            }
            '"' => {
                i += 1;
                while i < c.len() && c[i] != '"' {
                    i += if c[i] == '\\' { 2 } else { 1 };
                }
                i += 1;
                out.push_str("\"\"");
            }
            '\'' => {
                // A character literal ('x', '\n', '\u{1F600}', '{') or a lifetime ('a).
                if next == Some('\\') {
                    i += 2;
                    while i < c.len() && c[i] != '\'' {
                        i += 1;
                    }
                    i += 1;
                    out.push_str("' '");
                } else if c.get(i + 2) == Some(&'\'') {
                    i += 3;
                    out.push_str("' '");
                } else {
                    out.push('\'');
                    i += 1;
                }
            }
            ch => {
                out.push(ch);
                i += 1;
            }
        }
    }
    out
}

/// Where the raw string whose `#`s or quote start at `i` ends (just past it), if one does.
fn raw_string_end(c: &[char], i: usize) -> Option<usize> {
    let hashes = c[i..].iter().take_while(|&&ch| ch == '#').count();
    if c.get(i + hashes) != Some(&'"') {
        return None;
    }
    let mut j = i + hashes + 1;
    while j < c.len() {
        if c[j] == '"'
            && c[j + 1..]
                .iter()
                .take(hashes)
                .filter(|&&ch| ch == '#')
                .count()
                == hashes
        {
            return Some(j + 1 + hashes);
        }
        j += 1;
    }
    Some(c.len())
}

/// `code` (comments gone) without the items under `#[cfg(test)]`, and the names of the
/// `#[cfg(test)] mod x;` it declared.
fn strip_test_items(code: &str) -> (String, Vec<String>) {
    const MARK: &str = "#[cfg(test)]";
    let mut out = String::with_capacity(code.len());
    let mut mods = Vec::new();
    let mut rest = code;
    while let Some(at) = rest.find(MARK) {
        out.push_str(&rest[..at]);
        let b = &rest.as_bytes()[at + MARK.len()..];
        let mut i = 0;
        // Further attributes on the same item.
        loop {
            while i < b.len() && b[i].is_ascii_whitespace() {
                i += 1;
            }
            if b.get(i) == Some(&b'#') && b.get(i + 1) == Some(&b'[') {
                i = matching(b, i + 1).map_or(b.len(), |e| e + 1);
            } else {
                break;
            }
        }
        // The item: up to a `;` outside brackets, or the end of its first brace block.
        let start = i;
        let mut depth = 0i32;
        while i < b.len() {
            match b[i] {
                b'(' | b'[' => depth += 1,
                b')' | b']' => depth -= 1,
                b';' if depth == 0 => {
                    let item = &rest[at + MARK.len() + start..at + MARK.len() + i];
                    let words: Vec<&str> = item.split_whitespace().collect();
                    if let Some(p) = words.iter().position(|w| *w == "mod")
                        && let Some(name) = words.get(p + 1)
                    {
                        mods.push((*name).to_owned());
                    }
                    i += 1;
                    break;
                }
                b'{' if depth == 0 => {
                    i = matching(b, i).map_or(b.len(), |e| e + 1);
                    break;
                }
                _ => {}
            }
            i += 1;
        }
        rest = &rest[(at + MARK.len() + i).min(rest.len())..];
    }
    out.push_str(rest);
    (out, mods)
}

/// The index of the bracket closing the one at `open`.
fn matching(b: &[u8], open: usize) -> Option<usize> {
    let (o, c) = match b[open] {
        b'{' => (b'{', b'}'),
        b'[' => (b'[', b']'),
        _ => (b'(', b')'),
    };
    let mut depth = 0;
    for (j, &ch) in b.iter().enumerate().skip(open) {
        if ch == o {
            depth += 1;
        } else if ch == c {
            depth -= 1;
            if depth == 0 {
                return Some(j);
            }
        }
    }
    None
}

/// A token: an identifier (`$crate` included), `::`, or any other character.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Tok {
    /// An identifier or keyword.
    Ident(String),
    /// `::`.
    Path,
    /// Any other character.
    Punct(char),
}

/// `code`'s tokens, whitespace dropped.
fn tokens(code: &str) -> Vec<Tok> {
    let c: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    let ident = |ch: char| ch.is_alphanumeric() || ch == '_';
    while i < c.len() {
        let ch = c[i];
        if ch.is_whitespace() {
            i += 1;
        } else if ident(ch) || (ch == '$' && c.get(i + 1).is_some_and(|&n| ident(n))) {
            let start = i;
            i += 1;
            while i < c.len() && ident(c[i]) {
                i += 1;
            }
            let word: String = c[start..i].iter().collect();
            // `r#type`: the raw identifier `type`.
            out.push(Tok::Ident(word));
        } else if ch == ':' && c.get(i + 1) == Some(&':') {
            out.push(Tok::Path);
            i += 2;
        } else {
            out.push(Tok::Punct(ch));
            i += 1;
        }
    }
    out
}

/// Reads a file's tokens into its scope and the inline modules in it.
fn read_scope(krate: &mut Crate, file_key: &str, toks: &[Tok]) {
    let file = krate.scopes[file_key].file.clone();
    // The open inline modules: (scope key, brace depth its body opened at).
    let mut open: Vec<(String, usize)> = vec![(file_key.to_owned(), 0)];
    let mut depth = 0usize;
    let mut i = 0;
    while i < toks.len() {
        let here = open.last().expect("the file's scope").0.clone();
        match &toks[i] {
            Tok::Punct('{') => depth += 1,
            Tok::Punct('}') => {
                depth = depth.saturating_sub(1);
                if open.len() > 1 && open.last().is_some_and(|(_, d)| *d == depth) {
                    open.pop();
                }
            }
            Tok::Ident(w) if w == "use" => {
                let mut items = Vec::new();
                i = use_tree(toks, i + 1, Vec::new(), &mut items);
                let scope = krate.scopes.get_mut(&here).expect("scope");
                for it in items {
                    scope.paths.push(it.path.clone());
                    scope.uses.push(it);
                }
                continue;
            }
            Tok::Ident(w)
                if w == "macro_rules"
                    && toks.get(i + 1) == Some(&Tok::Punct('!'))
                    && word(toks.get(i + 2)).is_some() =>
            {
                let name = word(toks.get(i + 2)).unwrap_or_default().to_owned();
                krate
                    .scopes
                    .get_mut(&here)
                    .expect("scope")
                    .items
                    .insert(name);
            }
            Tok::Ident(w)
                if matches!(
                    w.as_str(),
                    "struct"
                        | "enum"
                        | "fn"
                        | "trait"
                        | "type"
                        | "const"
                        | "static"
                        | "union"
                        | "mod"
                ) && word(toks.get(i + 1)).is_some() =>
            {
                let name = word(toks.get(i + 1)).unwrap_or_default().to_owned();
                if w == "mod" && toks.get(i + 2) == Some(&Tok::Punct('{')) {
                    let key = krate.child_key(&here, &name);
                    krate
                        .scopes
                        .get_mut(&here)
                        .expect("scope")
                        .children
                        .insert(name.clone());
                    let inline = krate.scopes.entry(key.clone()).or_default();
                    inline.file_module = file_key.to_owned();
                    inline.file.clone_from(&file);
                    inline.parent = Some(here.clone());
                    open.push((key, depth));
                    // The `{` is counted when read.
                    i += 2;
                    continue;
                }
                krate
                    .scopes
                    .get_mut(&here)
                    .expect("scope")
                    .items
                    .insert(name);
            }
            Tok::Ident(w)
                if toks.get(i + 1) == Some(&Tok::Path)
                    && i.checked_sub(1).is_none_or(|p| toks[p] != Tok::Path) =>
            {
                // A path: its segments up to the first thing that is not `ident ::`.
                let mut path = vec![w.clone()];
                let mut j = i + 1;
                while toks.get(j) == Some(&Tok::Path) {
                    match toks.get(j + 1) {
                        Some(Tok::Ident(s)) => path.push(s.clone()),
                        _ => break,
                    }
                    j += 2;
                }
                krate.scopes.get_mut(&here).expect("scope").paths.push(path);
                i = j;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
}

/// The identifier `t` is, if it is one.
fn word(t: Option<&Tok>) -> Option<&str> {
    match t {
        Some(Tok::Ident(w)) => Some(w.as_str()),
        _ => None,
    }
}

/// Reads the `use` tree starting at `i` under `prefix` into `out`; returns where it ends.
fn use_tree(toks: &[Tok], mut i: usize, prefix: Vec<String>, out: &mut Vec<UseItem>) -> usize {
    let mut path = prefix;
    loop {
        match toks.get(i) {
            Some(Tok::Path) => i += 1,
            Some(Tok::Punct('{')) => {
                i += 1;
                loop {
                    match toks.get(i) {
                        Some(Tok::Punct('}')) => return i + 1,
                        Some(Tok::Punct(',')) => i += 1,
                        None => return i,
                        Some(_) => i = use_tree(toks, i, path.clone(), out),
                    }
                }
            }
            Some(Tok::Punct('*')) => {
                out.push(UseItem {
                    path,
                    name: None,
                    glob: true,
                });
                return i + 1;
            }
            Some(Tok::Ident(s)) => {
                path.push(s.clone());
                i += 1;
                if toks.get(i) == Some(&Tok::Path) {
                    continue;
                }
                let mut name = Some(s.clone());
                if s == "self" {
                    path.pop();
                    name = path.last().cloned();
                }
                if toks.get(i) == Some(&Tok::Ident("as".to_owned())) {
                    name = match toks.get(i + 1) {
                        Some(Tok::Ident(a)) if a != "_" => Some(a.clone()),
                        _ => None,
                    };
                    i += 2;
                }
                if !path.is_empty() {
                    out.push(UseItem {
                        path,
                        name,
                        glob: false,
                    });
                }
                // A top-level tree ends at `;`; a nested one at `,` or `}`.
                if toks.get(i) == Some(&Tok::Punct(';')) {
                    return i + 1;
                }
                return i;
            }
            Some(Tok::Punct(';')) => return i + 1,
            _ => return i + 1,
        }
    }
}
