//! Tidy checks in the manner of rust-analyzer's: the repository's own
//! rules about its layout, which no compiler checks.
//!
//! - docs/architecture.md's code map names every source file of every
//!   crate, and names no file that does not exist;
//! - every source file opens with a `//!` header that says what it is for;
//! - each crate depends only on the layers below it (the compiler then
//!   refuses any import of a layer above, as the crate is not a
//!   dependency);
//! - what the language and the renderer pull in, transitively, holds none
//!   of the crates only the applications need, and no C or C++ build;
//! - the binary holds no path of the folder it was built in, so no output
//!   of an installed binary can point into it;
//! - every error of a failed read or write carries the one `FileError`
//!   rather than wording `cannot read `path`: reason` again.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The workspace's crates, lowest first, with the `raytracer-*` crates
/// each may depend on: a layer names only layers below it.
const LAYERS: [(&str, &str, &[&str]); 6] = [
    ("raytracer-scene", "crates/scene", &[]),
    ("raytracer-render", "crates/render", &["raytracer-scene"]),
    ("raytracer-box", "crates/box", &[]),
    (
        "raytracer-app",
        "crates/app",
        &["raytracer-scene", "raytracer-render", "raytracer-box"],
    ),
    ("raytracer", ".", &["raytracer-app", "raytracer-scene"]),
    (
        "raytracer-web",
        "crates/web",
        &["raytracer-scene", "raytracer-render"],
    ),
];

fn repository() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The `.rs` files under `dir`, relative to it, sorted.
fn sources(dir: &Path) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap().flatten() {
            let path = entry.path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let relative = path.strip_prefix(dir).unwrap();
                found.insert(relative.to_string_lossy().replace('\\', "/"));
            }
        }
    }
    found
}

/// The `src` folder of each crate, as the code map's headings name them.
fn crate_sources() -> Vec<(String, PathBuf)> {
    LAYERS
        .iter()
        .map(|(_, folder, _)| {
            let heading = if *folder == "." {
                "src".to_string()
            } else {
                format!("{folder}/src")
            };
            (heading.clone(), repository().join(heading))
        })
        .collect()
}

/// The code map: for each `### `FOLDER`` heading under `## Code map`,
/// every backticked `*.rs` path of its section (up to the next `###`).
fn code_map() -> Vec<(String, BTreeSet<String>)> {
    let doc = std::fs::read_to_string(repository().join("docs/architecture.md")).unwrap();
    let map = &doc[doc.find("\n## Code map\n").expect("a code map")..];
    let map = &map[..map[1..].find("\n## ").map_or(map.len(), |end| end + 1)];
    map.split("\n### ")
        .skip(1)
        .filter_map(|section| section.strip_prefix('`'))
        .map(|section| {
            let (heading, body) = section.split_once('\n').unwrap_or((section, ""));
            let folder = heading.trim_end_matches('`').to_string();
            let files = body
                .split('`')
                .skip(1)
                .step_by(2)
                .filter(|word| word.ends_with(".rs"))
                .map(str::to_string)
                .collect();
            (folder, files)
        })
        .collect()
}

#[test]
fn the_code_map_names_every_source_file_and_no_other() {
    let map = code_map();
    for (folder, dir) in crate_sources() {
        let Some((_, listed)) = map.iter().find(|(f, _)| *f == folder) else {
            panic!("docs/architecture.md's code map has no `### `{folder}`` section");
        };
        let on_disk = sources(&dir);
        let missing: Vec<_> = on_disk.difference(listed).collect();
        assert!(
            missing.is_empty(),
            "docs/architecture.md's code map does not name these files of {folder}: {missing:?}"
        );
        let gone: Vec<_> = listed.difference(&on_disk).collect();
        assert!(
            gone.is_empty(),
            "docs/architecture.md's code map names files {folder} does not have: {gone:?}"
        );
    }
}

#[test]
fn every_source_file_opens_with_a_header() {
    for (folder, dir) in crate_sources() {
        for file in sources(&dir) {
            let text = std::fs::read_to_string(dir.join(&file)).unwrap();
            assert!(
                text.starts_with("//! "),
                "{folder}/{file} does not open with a `//!` header saying what it is for"
            );
        }
    }
}

/// An error message that names a file it could not read or write and then
/// its own reason: the shape `FileError` (in `raytracer_scene::failure`)
/// owns, written again.
fn words_its_own_file_error(line: &str) -> bool {
    let Some(message) = line.trim().strip_prefix("#[error(\"cannot ") else {
        return false;
    };
    ["read", "write", "open", "watch"]
        .iter()
        .any(|verb| message.starts_with(verb))
        && message.contains("`: {")
}

#[test]
fn file_errors_have_one_shape() {
    let mut found = Vec::new();
    for (folder, dir) in crate_sources() {
        for file in sources(&dir) {
            let text = std::fs::read_to_string(dir.join(&file)).unwrap();
            for (number, line) in text.lines().enumerate() {
                if file != "failure.rs" && words_its_own_file_error(line) {
                    found.push(format!("{folder}/{file}:{}: {}", number + 1, line.trim()));
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "these errors word a failed read or write themselves; carry a `FileError` instead:\n{}",
        found.join("\n")
    );
    assert!(words_its_own_file_error(
        r#"    #[error("cannot write `{path}`: {reason}")]"#
    ));
}

/// The `raytracer-*` crates a Cargo.toml names in `[table]`.
fn workspace_dependencies(manifest: &str, table: &str) -> BTreeSet<String> {
    let Some(start) = manifest.find(&format!("\n[{table}]\n")) else {
        return BTreeSet::new();
    };
    let body = &manifest[start + table.len() + 4..];
    let body = &body[..body.find("\n[").unwrap_or(body.len())];
    body.lines()
        .filter_map(|line| line.split_once(['=', '.']))
        .map(|(name, _)| name.trim().to_string())
        .filter(|name| name.starts_with("raytracer-"))
        .collect()
}

#[test]
fn each_layer_depends_only_on_the_layers_below() {
    for (name, folder, allowed) in LAYERS {
        let manifest =
            std::fs::read_to_string(repository().join(folder).join("Cargo.toml")).unwrap();
        let allowed: BTreeSet<String> = allowed.iter().map(|s| s.to_string()).collect();
        for table in ["dependencies", "dev-dependencies", "build-dependencies"] {
            let named = workspace_dependencies(&manifest, table);
            let above: Vec<_> = named.difference(&allowed).collect();
            // The binary's tests may use the renderer directly.
            let above: Vec<_> = above
                .into_iter()
                .filter(|dep| {
                    !(name == "raytracer"
                        && table == "dev-dependencies"
                        && *dep == "raytracer-render")
                })
                .collect();
            assert!(
                above.is_empty(),
                "{name} names {above:?} in [{table}]; it may name only {allowed:?} (docs/architecture.md)"
            );
        }
    }
}

/// The crates `package` depends on, transitively, as built (not its tests).
fn dependency_closure(package: &str) -> BTreeSet<String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let output = Command::new(cargo)
        .current_dir(repository())
        .args([
            "tree",
            "--locked",
            "--offline",
            "-e",
            "normal",
            "--prefix",
            "none",
            "-p",
            package,
        ])
        .output()
        .expect("run cargo tree");
    assert!(
        output.status.success(),
        "cargo tree -p {package}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8(output.stdout)
        .unwrap()
        .lines()
        .filter_map(|line| line.split_whitespace().next())
        .map(str::to_string)
        .collect()
}

#[test]
fn the_language_and_the_renderer_pull_in_no_application_crate() {
    let app = std::fs::read_to_string(repository().join("crates/app/Cargo.toml")).unwrap();
    let declared = |manifest: &str| -> BTreeSet<String> {
        let start = manifest.find("\n[dependencies]\n").unwrap() + 16;
        let body = &manifest[start..];
        let body = &body[..body.find("\n[").unwrap_or(body.len())];
        body.lines()
            .filter_map(|line| line.split_once(['=', '.']))
            .map(|(name, _)| name.trim().to_string())
            .filter(|name| !name.is_empty() && !name.starts_with('#'))
            .filter(|name| !name.starts_with("raytracer"))
            .collect()
    };
    let renderer = dependency_closure("raytracer-render");
    let language = dependency_closure("raytracer-scene");
    let lower: BTreeSet<String> = ["crates/scene/Cargo.toml", "crates/render/Cargo.toml"]
        .iter()
        .flat_map(|m| declared(&std::fs::read_to_string(repository().join(m)).unwrap()))
        .collect();
    // The crates only the applications ask for, and `cc`, which builds C
    // and C++ (ꟻLIP's), must reach neither lower layer.
    let application_only: BTreeSet<String> = declared(&app)
        .difference(&lower)
        .cloned()
        .chain(["cc".to_string()])
        .collect();
    assert!(application_only.contains("clap") && application_only.contains("nv-flip"));
    let playground = dependency_closure("raytracer-web");
    for (layer, closure) in [
        ("raytracer-scene", &language),
        ("raytracer-render", &renderer),
        ("raytracer-web", &playground),
    ] {
        assert!(
            closure.contains("glam"),
            "cargo tree listed nothing for {layer}"
        );
        let leaked: Vec<_> = closure.intersection(&application_only).collect();
        assert!(
            leaked.is_empty(),
            "{layer} pulls in {leaked:?}, which only the applications may need"
        );
    }
}

/// Where `unsafe` code may be: the box (`raytracer-box`, all of grading's
/// system calls), the renderer's AVX2 kernels, and the playground's C ABI
/// (whose `#[no_mangle]` the lint counts). The language and the
/// applications forbid it in their crate roots, so the compiler holds them.
#[test]
fn unsafe_code_lives_in_the_box_and_the_kernels_alone() {
    for root in ["crates/scene/src/lib.rs", "crates/app/src/lib.rs"] {
        let text = std::fs::read_to_string(repository().join(root)).unwrap();
        assert!(
            text.contains("\n#![forbid(unsafe_code)]\n"),
            "{root} does not forbid `unsafe` code"
        );
    }
    let allowed = |file: &str| {
        file.starts_with("crates/box/src/")
            || file == "crates/render/src/render/sampling.rs"
            || file == "crates/render/src/render/world.rs"
    };
    for (heading, dir) in crate_sources() {
        for file in sources(&dir) {
            let path = format!("{heading}/{file}");
            let text = std::fs::read_to_string(dir.join(&file)).unwrap();
            let uses = text.contains("unsafe {") || text.contains("unsafe fn ");
            assert!(
                !uses || allowed(&path),
                "{path} holds `unsafe` code: grading's belongs in crates/box (docs/architecture.md)"
            );
        }
    }
}

/// What `cargo install` builds, the release binary: a debug build keeps
/// its build folder in its debug information by design, so the test runs
/// where the binary under test is a release one (`make test`).
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "a debug binary keeps its build folder in its debug information; `make test` checks the release binary"
)]
fn the_binary_holds_no_path_of_its_build_folder() {
    let binary = std::fs::read(env!("CARGO_BIN_EXE_raytracer")).unwrap();
    let folder = repository().to_string_lossy().into_owned();
    assert!(
        !binary
            .windows(folder.len())
            .any(|window| window == folder.as_bytes()),
        "the binary holds `{folder}`: a link or message of an installed binary would point into the folder it was built in"
    );
}

/// The module path of a source file: `grade/aspects/mod.rs` is
/// `grade::aspects`, `lib.rs` the crate root (empty).
fn module_path(file: &str) -> Vec<String> {
    let mut parts: Vec<String> = file
        .trim_end_matches(".rs")
        .split('/')
        .map(str::to_string)
        .collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        parts.pop();
    }
    parts
}

/// The paths a piece of code names after `prefix` (`crate::`, `super::`,
/// `self::`, a child module's `name::`): each path's segments, with one
/// path per item of a `{…}` group.
fn paths_after(code: &str, prefix: &str) -> Vec<Vec<String>> {
    fn ident(text: &str) -> String {
        text.chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    }
    fn walk(rest: &str, so_far: Vec<String>, found: &mut Vec<Vec<String>>) {
        let rest = rest.trim_start();
        if let Some(group) = rest.strip_prefix('{') {
            let mut depth = 0;
            let mut start = 0;
            for (i, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => {
                        walk(&group[start..i], so_far.clone(), found);
                        return;
                    }
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        walk(&group[start..i], so_far.clone(), found);
                        start = i + 1;
                    }
                    _ => {}
                }
            }
            return;
        }
        let name = ident(rest);
        if name.is_empty() {
            found.push(so_far);
            return;
        }
        let mut path = so_far;
        path.push(name.clone());
        match rest[name.len()..].strip_prefix("::") {
            Some(more) => walk(more, path, found),
            None => found.push(path),
        }
    }
    let mut found = Vec::new();
    for (i, _) in code.match_indices(prefix) {
        let before = code[..i].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
            continue;
        }
        walk(&code[i + prefix.len()..], Vec::new(), &mut found);
    }
    found
}

/// The modules of the crate in `src` compiled only for tests: those
/// declared under `#[cfg(test)]` by their parent.
fn test_only_modules(src: &Path) -> BTreeSet<Vec<String>> {
    sources(src)
        .iter()
        .flat_map(|file| {
            let text = std::fs::read_to_string(src.join(file)).unwrap();
            let parent = module_path(file);
            text.split("#[cfg(test)]\n")
                .skip(1)
                .filter_map(|rest| {
                    let rest = rest.trim_start();
                    let rest = rest.strip_prefix("pub ").unwrap_or(rest);
                    let name = rest.strip_prefix("mod ")?.split_once(';')?.0;
                    (!name.contains(char::is_whitespace)).then(|| name.to_string())
                })
                .map(move |name| {
                    let mut path = parent.clone();
                    path.push(name);
                    path
                })
                .collect::<Vec<_>>()
        })
        .collect()
}

/// Which source files of the crate in `src` each file imports, in code
/// outside unit tests: every `crate::`, `super::` and `self::` path and
/// every path through a child module the file declares, resolved to the
/// deepest module it names. A file's `mod child;` declaration is not an
/// import, nor is a path between a module and one of its ancestors: a
/// folder's root module holds the vocabulary its children share and
/// dispatches to them, as a crate root does. Every other path counts, so
/// siblings or cousins that name each other are a cycle.
fn module_graph(src: &Path) -> std::collections::BTreeMap<String, BTreeSet<String>> {
    let mut graph: std::collections::BTreeMap<String, BTreeSet<String>> = Default::default();
    let files = sources(src);
    let modules: std::collections::BTreeMap<Vec<String>, String> = files
        .iter()
        .map(|file| (module_path(file), file.clone()))
        .collect();
    let test_only = test_only_modules(src);
    for file in files
        .iter()
        .filter(|f| !f.ends_with("tests.rs") && !test_only.contains(&module_path(f)))
    {
        let me = module_path(file);
        let text = std::fs::read_to_string(src.join(file)).unwrap();
        let code = text.split("#[cfg(test)]\nmod tests").next().unwrap();
        let code: String = code
            .lines()
            .map(|line| line.split("//").next().unwrap())
            .collect::<Vec<_>>()
            .join("\n");
        let children: Vec<String> = code
            .lines()
            .filter_map(|line| {
                let line = line.trim();
                let line = line.strip_prefix("pub ").unwrap_or(line);
                let line = line.strip_prefix("pub(crate) ").unwrap_or(line);
                line.strip_prefix("mod ")?
                    .strip_suffix(';')
                    .map(str::to_string)
            })
            .collect();
        let mut named: Vec<Vec<String>> = Vec::new();
        named.extend(paths_after(&code, "crate::"));
        for path in paths_after(&code, "self::") {
            named.push(me.iter().cloned().chain(path).collect());
        }
        for path in paths_after(&code, "super::") {
            let mut base = me.clone();
            let mut rest = path.as_slice();
            base.pop();
            while rest.first().is_some_and(|s| s == "super") {
                base.pop();
                rest = &rest[1..];
            }
            named.push(base.into_iter().chain(rest.iter().cloned()).collect());
        }
        for child in &children {
            for path in paths_after(&code, &format!("{child}::")) {
                let mut full = me.clone();
                full.push(child.clone());
                full.extend(path);
                named.push(full);
            }
        }
        let imports = graph.entry(file.clone()).or_default();
        for path in named {
            let target = (0..=path.len())
                .rev()
                .find_map(|len| modules.get(&path[..len]))
                .expect("the crate root is a module");
            let there = module_path(target);
            let related = there.starts_with(&me) || me.starts_with(&there);
            if !related && !test_only.contains(&there) {
                imports.insert(target.clone());
            }
        }
    }
    graph
}

/// The cycles of `graph`: its strongly connected components of more than
/// one module (Tarjan's algorithm), each sorted.
fn cycles(graph: &std::collections::BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct Walk<'a> {
        graph: &'a std::collections::BTreeMap<String, BTreeSet<String>>,
        index: std::collections::BTreeMap<&'a str, usize>,
        low: std::collections::BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        found: Vec<Vec<String>>,
    }
    impl<'a> Walk<'a> {
        fn visit(&mut self, node: &'a str) {
            let at = self.index.len();
            self.index.insert(node, at);
            self.low.insert(node, at);
            self.stack.push(node);
            for next in self.graph.get(node).into_iter().flatten() {
                if !self.index.contains_key(next.as_str()) {
                    self.visit(next);
                    let low = self.low[node].min(self.low[next.as_str()]);
                    self.low.insert(node, low);
                } else if self.stack.contains(&next.as_str()) {
                    let low = self.low[node].min(self.index[next.as_str()]);
                    self.low.insert(node, low);
                }
            }
            if self.low[node] == self.index[node] {
                let start = self.stack.iter().rposition(|n| *n == node).unwrap();
                let mut component: Vec<String> =
                    self.stack.drain(start..).map(str::to_string).collect();
                if component.len() > 1 {
                    component.sort();
                    self.found.push(component);
                }
            }
        }
    }
    let mut walk = Walk {
        graph,
        index: Default::default(),
        low: Default::default(),
        stack: Vec::new(),
        found: Vec::new(),
    };
    for node in graph.keys() {
        if !walk.index.contains_key(node.as_str()) {
            walk.visit(node);
        }
    }
    walk.found
}

#[test]
fn no_crate_has_a_module_cycle() {
    // The binary and the playground's module are one file each.
    let one_file = |folder: &str| matches!(folder, "." | "crates/web");
    let mut found = Vec::new();
    for (_, folder, _) in LAYERS.iter().filter(|(_, folder, _)| !one_file(folder)) {
        let graph = module_graph(&repository().join(folder).join("src"));
        assert!(graph.len() > 3, "{folder}: no modules found");
        for cycle in cycles(&graph) {
            found.push(format!("{folder}: {}", cycle.join(", ")));
        }
    }
    assert!(
        found.is_empty(),
        "these modules import each other in a cycle (docs/architecture.md, Invariants):\n{}",
        found.join("\n")
    );
}

/// The scene crate's modules from the bottom up, as docs/architecture.md's
/// invariants state them: a module may import only modules of its own
/// level or below.
const SCENE_LEVELS: [&[&str]; 7] = [
    &[
        "span", "ast", "language", "limits", "suggest", "escape", "failure", "encoding",
        "geometry", "texture", "folder",
    ],
    &["fix", "line_index", "model"],
    &["syntax"],
    &["diagnostic"],
    &["json"],
    &["check", "format", "convert"],
    &["frontend"],
];

#[test]
fn the_scene_crate_imports_in_its_stated_order() {
    let level = |module: &str| {
        SCENE_LEVELS
            .iter()
            .position(|names| names.contains(&module))
    };
    let top = |file: &str| module_path(file).first().cloned().unwrap_or_default();
    let graph = module_graph(&repository().join("crates/scene/src"));
    let mut wrong = Vec::new();
    for (file, imports) in &graph {
        let from = top(file);
        if from.is_empty() {
            continue;
        }
        let Some(at) = level(&from) else {
            panic!(
                "`{from}` is at no level of SCENE_LEVELS: add it here and in docs/architecture.md"
            );
        };
        for target in imports {
            let to = top(target);
            if level(&to).is_some_and(|there| there > at) {
                wrong.push(format!("{file} imports `{to}`, a level above `{from}`"));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    // The doc states the same order, level by level.
    let doc = std::fs::read_to_string(repository().join("docs/architecture.md")).unwrap();
    let doc = doc.replace("\n  ", " ");
    let stated = doc
        .split("in `raytracer-scene`, ")
        .nth(1)
        .expect("docs/architecture.md states the scene crate's order");
    let stated = &stated[..stated
        .find("drives them all")
        .expect("the order ends with `frontend`")];
    let mut at = 0;
    for names in SCENE_LEVELS {
        for name in names {
            let found = stated
                .find(&format!("`{name}`"))
                .unwrap_or_else(|| panic!("docs/architecture.md's order does not name `{name}`"));
            assert!(
                found >= at,
                "docs/architecture.md names `{name}` before a module of a level below it"
            );
        }
        at = names
            .iter()
            .map(|name| stated.find(&format!("`{name}`")).unwrap())
            .max()
            .unwrap();
    }
}

/// The non-test code of each source file of the crate in `src`, comments
/// left out.
fn non_test_code(src: &Path) -> Vec<(String, String)> {
    let test_only = test_only_modules(src);
    sources(src)
        .into_iter()
        .filter(|file| !file.ends_with("tests.rs") && !test_only.contains(&module_path(file)))
        .map(|file| {
            let text = std::fs::read_to_string(src.join(&file)).unwrap();
            let code = text.split("#[cfg(test)]").next().unwrap();
            let code: Vec<&str> = code
                .lines()
                .map(|line| line.split("//").next().unwrap())
                .collect();
            (file, code.join("\n"))
        })
        .collect()
}

#[test]
fn the_language_reads_no_clock() {
    for (file, code) in non_test_code(&repository().join("crates/scene/src")) {
        for clock in ["Instant", "SystemTime", "std::time"] {
            assert!(
                !code.contains(clock),
                "crates/scene/src/{file} names `{clock}`: the language reads no clock (docs/architecture.md)"
            );
        }
    }
}

#[test]
fn the_language_touches_files_only_in_the_front_end_and_the_texture_loaders() {
    for (file, code) in non_test_code(&repository().join("crates/scene/src")) {
        if file.starts_with("frontend/") || file == "texture.rs" {
            continue;
        }
        for io in ["std::fs", "File::", "OpenOptions"] {
            let named = code.match_indices(io).any(|(i, _)| {
                !code[..i]
                    .chars()
                    .next_back()
                    .is_some_and(|c| c.is_alphanumeric() || c == '_')
            });
            assert!(
                !named,
                "crates/scene/src/{file} names `{io}`: the analysis does no I/O of its own (docs/architecture.md)"
            );
        }
    }
}

#[test]
fn the_renderer_never_reads_the_syntax_tree() {
    for (file, code) in non_test_code(&repository().join("crates/render/src")) {
        for tree in [
            "raytracer_scene::ast",
            "raytracer_scene::syntax",
            "raytracer_scene::json",
        ] {
            assert!(
                !code.contains(tree),
                "crates/render/src/{file} names `{tree}`: the renderer sees only `ir::Scene` (docs/architecture.md)"
            );
        }
    }
}

#[test]
fn the_fuzz_targets_name_only_the_crates_the_map_allows() {
    let manifest = std::fs::read_to_string(repository().join("fuzz/Cargo.toml")).unwrap();
    let named = workspace_dependencies(&manifest, "dependencies");
    assert!(
        named.contains("raytracer-scene"),
        "fuzz/Cargo.toml names no crate of ours: {named:?}"
    );
    // The language server's edits are a target too: `raytracer-app`'s
    // `lsp::Document`.
    let allowed: BTreeSet<String> = ["raytracer-scene", "raytracer-render", "raytracer-app"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let above: Vec<_> = named.difference(&allowed).collect();
    assert!(
        above.is_empty(),
        "fuzz/Cargo.toml names {above:?}: the fuzz targets drive the language, the renderer and the language server (docs/architecture.md)"
    );
}

/// Every invariant of docs/architecture.md names the tests that hold it
/// (`` `FILE::TEST` ``), and each named test is a function of that file.
#[test]
fn every_invariant_names_tests_that_exist() {
    let doc = std::fs::read_to_string(repository().join("docs/architecture.md")).unwrap();
    let section = &doc[doc
        .find("\n## Invariants\n")
        .expect("an invariants section")..];
    let section = &section[1..];
    let section = &section[..section.find("\n## ").map_or(section.len(), |end| end + 1)];
    let invariants: Vec<&str> = section.split("\n- **").skip(1).collect();
    assert!(invariants.len() > 10, "no invariants found");
    for invariant in invariants {
        let name = invariant.split("**").next().unwrap();
        let tests: Vec<(&str, &str)> = invariant
            .split('`')
            .skip(1)
            .step_by(2)
            .filter_map(|word| word.split_once(".rs::"))
            .collect();
        assert!(
            !tests.is_empty(),
            "the invariant \"{name}\" names no test (`tests/FILE.rs::test`)"
        );
        for (file, test) in tests {
            let path = repository().join(format!("{file}.rs"));
            let text = std::fs::read_to_string(&path)
                .unwrap_or_else(|_| panic!("\"{name}\" names `{file}.rs`, which does not exist"));
            assert!(
                text.contains(&format!("fn {test}(")),
                "\"{name}\" names `{file}.rs::{test}`, which is no function of that file"
            );
        }
    }
}

/// A page's `## ` headings, outside code blocks.
fn headings(page: &str) -> Vec<&str> {
    let mut in_code = false;
    let mut found = Vec::new();
    for line in page.lines() {
        if line.starts_with("```") {
            in_code = !in_code;
        } else if !in_code {
            if let Some(heading) = line.strip_prefix("## ") {
                found.push(heading);
            }
        }
    }
    found
}

/// GitHub's anchor for a heading: lowercase, punctuation but `-` and `_`
/// dropped, spaces as `-`.
fn anchor(heading: &str) -> String {
    heading
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | ' '))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// Every long page (over 300 lines) of docs/ and its folders links each of
/// its `## ` sections from its top (a `## Contents` list, or a table such
/// as the codes of diagnostics/scene.md), so a reader finds a section
/// without scrolling through the page.
#[test]
fn every_long_page_has_a_table_of_contents() {
    fn markdown_files(folder: &Path, found: &mut Vec<std::path::PathBuf>) {
        for entry in std::fs::read_dir(folder).expect("a folder of docs/") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                markdown_files(&path, found);
            } else if path.extension().is_some_and(|e| e == "md") {
                found.push(path);
            }
        }
    }
    let mut pages = Vec::new();
    markdown_files(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("docs"),
        &mut pages,
    );
    let mut long = 0;
    for path in pages {
        let page = std::fs::read_to_string(&path).expect("a page");
        if page.lines().count() <= 300 {
            continue;
        }
        long += 1;
        let sections: Vec<&str> = headings(&page)
            .into_iter()
            .filter(|h| *h != "Contents")
            .collect();
        let first = sections.first().expect("a long page has sections");
        let top = &page[..page.find(&format!("\n## {first}\n")).expect("heading")];
        for section in &sections {
            assert!(
                top.contains(&format!("](#{})", anchor(section))),
                "{} does not link `## {section}` from its top (`## Contents`)",
                path.display()
            );
        }
    }
    assert!(long >= 5, "only {long} long pages");
}

/// The longest a function in grading's code may be, in lines from its
/// `fn` to its closing brace: longer, it no longer fits in one's head.
const MAX_FUNCTION_LINES: usize = 120;

/// `code` with its comments, strings and character literals blanked out
/// (newlines kept), so a brace in them is not counted as code.
fn blank_literals(code: &str) -> String {
    let bytes = code.as_bytes();
    let mut out = bytes.to_vec();
    let blank = |out: &mut Vec<u8>, from: usize, to: usize| {
        for byte in &mut out[from..to.min(bytes.len())] {
            if *byte != b'\n' {
                *byte = b' ';
            }
        }
    };
    let ident = |i: usize| i > 0 && (bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_');
    let mut i = 0;
    while i < bytes.len() {
        let rest = &bytes[i..];
        let end = if rest.starts_with(b"//") {
            rest.iter()
                .position(|&b| b == b'\n')
                .map_or(bytes.len(), |n| i + n)
        } else if rest.starts_with(b"/*") {
            let mut depth = 0;
            let mut j = i;
            while j < bytes.len() {
                if bytes[j..].starts_with(b"/*") {
                    depth += 1;
                    j += 2;
                } else if bytes[j..].starts_with(b"*/") {
                    depth -= 1;
                    j += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    j += 1;
                }
            }
            j
        } else if rest[0] == b'r'
            && (!ident(i) || (i > 0 && bytes[i - 1] == b'b' && !ident(i - 1)))
            && rest[1..].iter().find(|&&b| b != b'#') == Some(&b'"')
        {
            let hashes = rest[1..].iter().take_while(|&&b| b == b'#').count();
            let close: Vec<u8> = std::iter::once(b'"')
                .chain(std::iter::repeat_n(b'#', hashes))
                .collect();
            let body = i + 2 + hashes;
            bytes[body..]
                .windows(close.len())
                .position(|w| w == close.as_slice())
                .map_or(bytes.len(), |n| body + n + close.len())
        } else if rest[0] == b'"' {
            let mut j = i + 1;
            while j < bytes.len() && bytes[j] != b'"' {
                j += if bytes[j] == b'\\' { 2 } else { 1 };
            }
            j + 1
        } else if rest[0] == b'\'' && rest.get(1) == Some(&b'\\') {
            rest[2..]
                .iter()
                .position(|&b| b == b'\'')
                .map_or(bytes.len(), |n| i + 3 + n)
        } else if rest[0] == b'\'' {
            // A character literal is one character and a quote; a
            // lifetime (`'a`) has none after its name.
            let width = code[i + 1..].chars().next().map_or(1, char::len_utf8);
            if bytes.get(i + 1 + width) == Some(&b'\'') {
                i + 2 + width
            } else {
                i + 1
            }
        } else {
            i + 1
        };
        if end > i + 1 {
            blank(&mut out, i, end);
        }
        i = end.max(i + 1);
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Each `fn` item of `code` that has a body: its name, its first line
/// and its length in lines, from the `fn` to the closing brace.
fn function_lengths(code: &str) -> Vec<(String, usize, usize)> {
    let code = blank_literals(code);
    let bytes = code.as_bytes();
    let line_of = |at: usize| code[..at].matches('\n').count() + 1;
    let mut found = Vec::new();
    for (at, _) in code.match_indices("fn ") {
        if at > 0 && (bytes[at - 1].is_ascii_alphanumeric() || bytes[at - 1] == b'_') {
            continue;
        }
        let name: String = code[at + 3..]
            .trim_start()
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        if name.is_empty() {
            continue;
        }
        // The body's brace, or the `;` of a declaration without one, at
        // the signature's own level (an array type's `;` is in brackets).
        let mut depth = 0i32;
        let mut open = None;
        for (i, &byte) in bytes.iter().enumerate().skip(at) {
            match byte {
                b'(' | b'[' => depth += 1,
                b')' | b']' => depth -= 1,
                b';' if depth == 0 => break,
                b'{' if depth == 0 => {
                    open = Some(i);
                    break;
                }
                _ => {}
            }
        }
        let Some(open) = open else { continue };
        let mut depth = 0;
        for (i, &byte) in bytes.iter().enumerate().skip(open) {
            match byte {
                b'{' => depth += 1,
                b'}' => {
                    depth -= 1;
                    if depth == 0 {
                        let first = line_of(at);
                        found.push((name, first, line_of(i) - first + 1));
                        break;
                    }
                }
                _ => {}
            }
        }
    }
    found
}

/// The scanner counts lines of code, not braces in strings, characters,
/// comments or raw strings, and tells a lifetime from a character.
#[test]
fn the_function_scanner_skips_braces_in_literals() {
    let code = "fn short<'a>(x: &'a str) -> [u8; 2] {\n    let _ = \"}}\";\n    let _ = '}';\n    let _ = '\\'';\n    // }\n    /* } */\n    let _ = r#\"}\"#;\n    [0; 2]\n}\n\nfn declared(x: u8);\n\nfn after() {\n}\n";
    assert_eq!(
        function_lengths(code),
        vec![("short".to_string(), 1, 9), ("after".to_string(), 13, 2)]
    );
}

/// No function in grading (grade/, the command, the box) is over
/// [`MAX_FUNCTION_LINES`] lines.
#[test]
fn no_grading_function_is_over_120_lines() {
    let mut files: Vec<String> = sources(&repository().join("crates/app/src/grade"))
        .into_iter()
        .map(|file| format!("crates/app/src/grade/{file}"))
        .chain(
            sources(&repository().join("crates/box/src"))
                .into_iter()
                .map(|file| format!("crates/box/src/{file}")),
        )
        .collect();
    files.push("crates/app/src/commands/grade.rs".into());
    let mut long = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(repository().join(file)).unwrap();
        for (name, line, lines) in function_lengths(&text) {
            if lines > MAX_FUNCTION_LINES {
                long.push(format!("{file}:{line} `{name}` ({lines} lines)"));
            }
        }
    }
    assert!(
        long.is_empty(),
        "functions over {MAX_FUNCTION_LINES} lines: {long:?}; split them into functions that each do one thing"
    );
}
