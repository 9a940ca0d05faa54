//! The command-line examples of README.md and docs/ are tests: trycmd runs
//! every ```` ```console ```` block of each page in [`PAGES`] and of
//! [`GRADING_PAGE`] (a `$ raytracer
//! ...` line, then its output, stdout and stderr together; `? 1` after
//! the command for an exit code other than 0; `...` for lines left out,
//! `[..]` for part of a line) and fails with a diff when the program's
//! output drifts from the page. `TRYCMD=overwrite cargo test --release
//! --test integration docs::` writes the program's output into the pages.
//!
//! Each page runs in a folder of its own that trycmd makes and removes:
//! the repository's `scenes/` and the page's fixtures,
//! `tests/docs/<page>.in/` (README.md's are `tests/docs/README.in/`), at
//! 80 columns. A page's blocks run in order in that one folder, so a later
//! example sees the files an earlier one wrote. A block that is a shell
//! recipe rather than commands (a pipeline, a loop) is ```` ```sh ````,
//! and the test that runs it says so on the page.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::support::bin;

/// The pages whose examples run, relative to the repository, in
/// [`the_examples_in_the_docs_run_as_written`]; docs/grading.md's run in
/// [`the_grading_examples_run_as_written`].
const PAGES: &[&str] = &[
    "README.md",
    "docs/README.md",
    "docs/cli.md",
    "docs/distributed.md",
    "docs/formats.md",
    "docs/language.md",
    "docs/preview.md",
];

/// The page whose examples grade student tracers: they need a box (or
/// root) and `python3`, and take seconds each, so they run in a test of
/// their own, in the full tier (the Makefile's `FULL_TIER`).
const GRADING_PAGE: &str = "docs/grading.md";

/// The students docs/grading.md's examples grade, taken from
/// tests/students/ into its folder: (where, which tracer folder). `alice`
/// is a correct reading, `bob` casts no shadows; `mytracer` is alice's
/// program alone, run by its path as `--tracer './mytracer {scene} {out}'`.
const GRADING_STUDENTS: &[(&str, &str)] = &[
    ("students/alice", "tests/students/judge/correct_centres_py"),
    ("students/bob", "tests/students/judge/no_shadows"),
];

fn repo() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Copy the folder `from` into `to` (created), recursively.
fn copy_folder(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("create folder");
    for entry in std::fs::read_dir(from).expect("read folder") {
        let entry = entry.expect("entry");
        let target = to.join(entry.file_name());
        if entry.file_type().expect("type").is_dir() {
            copy_folder(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), &target).expect("copy file");
        }
    }
}

/// `docs/cli.md` -> `cli`, `README.md` -> `README`, `docs/README.md` ->
/// `docs-README`: the name of the page's fixture folder under tests/docs/.
fn fixture_name(page: &str) -> String {
    let stem = page.strip_suffix(".md").expect("a Markdown page");
    match stem.strip_prefix("docs/") {
        Some("README") => "docs-README".to_string(),
        Some(name) => name.to_string(),
        None => stem.to_string(),
    }
}

/// The programs the examples may run: this build of `raytracer`, `cat`
/// to show a fixture, and `cmp` to show two files are the same. trycmd skips, without failing, a command whose
/// program it was not given, so [`every_page_with_examples_runs_them`]
/// holds each example to these.
fn programs() -> Vec<(&'static str, PathBuf)> {
    let on_path = |name: &str| {
        std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default())
            .map(|dir| dir.join(name))
            .find(|path| path.is_file())
            .unwrap_or_else(|| panic!("`{name}` on PATH"))
    };
    vec![
        ("raytracer", PathBuf::from(bin())),
        ("cat", on_path("cat")),
        ("cmp", on_path("cmp")),
    ]
}

/// Lay `page` beside a folder of its fixtures in `root`, as trycmd runs
/// `X.md` in `X.in` (copied to a fresh folder when `X.out` exists): the
/// repository's `scenes/` and `tests/docs/<page>.in/`. Returns the copy.
fn lay_out(root: &Path, page: &str) -> PathBuf {
    let copy = root.join(fixture_name(page)).with_extension("md");
    std::fs::copy(repo().join(page), &copy).unwrap_or_else(|e| panic!("{page}: {e}"));
    let input = copy.with_extension("in");
    copy_folder(&repo().join("scenes"), &input.join("scenes"));
    let fixtures = repo().join("tests/docs").join(fixture_name(page) + ".in");
    if fixtures.is_dir() {
        copy_folder(&fixtures, &input);
    }
    std::fs::create_dir(copy.with_extension("out")).expect("out folder");
    copy
}

/// Run the examples of `pages`, laid out in `root` by [`lay_out`], with
/// `cases` (its programs registered here); under `TRYCMD=overwrite`, carry
/// the pages trycmd rewrote back into the repository.
fn run_pages(cases: trycmd::TestCases, copies: &[(PathBuf, &str)]) {
    for (name, path) in programs() {
        cases.register_bin(name, path);
    }
    cases.env("COLUMNS", "80").env("NO_COLOR", "1");
    for (copy, _) in copies {
        cases.case(copy);
    }
    // trycmd names the copies in what it prints: say which page each is.
    for (copy, page) in copies {
        let _ = writeln!(std::io::stderr(), "{page} runs as {}", copy.display());
    }
    cases.run();
    if std::env::var("TRYCMD").as_deref() == Ok("overwrite") {
        for (copy, page) in copies {
            std::fs::copy(copy, repo().join(page)).expect("write the page back");
        }
    }
}

#[test]
fn the_examples_in_the_docs_run_as_written() {
    let root = tempfile::tempdir().expect("temp dir");
    let copies: Vec<_> = PAGES
        .iter()
        .map(|page| (lay_out(root.path(), page), *page))
        .collect();
    let cases = trycmd::TestCases::new();
    // Every example ends well within the timeout but `preview`, a server
    // that runs until it is stopped: its example expects the stop
    // (`? interrupted`) after the line it printed.
    cases.timeout(std::time::Duration::from_secs(10));
    run_pages(cases, &copies);
}

/// docs/grading.md's examples, in a folder that also holds the students
/// of [`GRADING_STUDENTS`] and `mytracer`, with a reference cache of the
/// test's own (`XDG_CACHE_HOME`), which the page's examples share in
/// order: the first renders the references, the later ones find them.
#[test]
fn the_grading_examples_run_as_written() {
    use std::os::unix::fs::PermissionsExt;
    let root = tempfile::tempdir().expect("temp dir");
    let copy = lay_out(root.path(), GRADING_PAGE);
    let input = copy.with_extension("in");
    for (to, from) in GRADING_STUDENTS {
        copy_folder(&repo().join(from), &input.join(to));
    }
    let tracer = input.join("mytracer");
    std::fs::copy(input.join("students/alice/tracer.py"), &tracer).expect("copy mytracer");
    std::fs::set_permissions(&tracer, std::fs::Permissions::from_mode(0o755)).expect("chmod");
    let cache = root.path().join("cache");
    let cases = trycmd::TestCases::new();
    // A class of two on the built-in suite takes seconds alone, minutes on
    // a loaded machine.
    cases
        .env("XDG_CACHE_HOME", cache.to_str().expect("a UTF-8 path"))
        .timeout(std::time::Duration::from_secs(300));
    run_pages(cases, &[(copy, GRADING_PAGE)]);
}

/// README.md and every Markdown page under docs/ (its folders too), each
/// as (its path in the repository, its text).
fn all_pages() -> Vec<(String, String)> {
    fn walk(folder: &Path, found: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(folder).expect("read folder") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                walk(&path, found);
            } else if path.extension().is_some_and(|e| e == "md") {
                found.push(path);
            }
        }
    }
    let mut paths = vec![repo().join("README.md")];
    walk(&repo().join("docs"), &mut paths);
    paths.sort();
    paths
        .into_iter()
        .map(|path| {
            let page = path
                .strip_prefix(repo())
                .expect("in the repository")
                .to_string_lossy()
                .replace('\\', "/");
            let text = std::fs::read_to_string(&path).expect("read page");
            (page, text)
        })
        .collect()
}

/// The fenced blocks of a page: (the line after its opening fence,
/// 1-based; its language; its lines).
fn blocks(text: &str) -> Vec<(usize, &str, Vec<&str>)> {
    let mut found = Vec::new();
    let mut open: Option<(usize, &str, Vec<&str>)> = None;
    for (number, line) in text.lines().enumerate() {
        match &mut open {
            None if line.starts_with("```") => {
                open = Some((number + 2, line[3..].trim(), Vec::new()))
            }
            Some(_) if line.starts_with("```") => found.extend(open.take()),
            Some((_, _, lines)) => lines.push(line),
            None => {}
        }
    }
    found
}

/// Every page with a command example, README.md and docs/ alike, is among
/// those whose examples run ([`PAGES`], [`GRADING_PAGE`]); a `$ ` command
/// line appears only in a ```` ```console ```` block, which trycmd runs
/// (not in `sh`, `text`, or a block of no language); and each console
/// command is a program trycmd is given.
#[test]
fn every_page_with_examples_runs_them() {
    let programs: Vec<&str> = programs().iter().map(|(name, _)| *name).collect();
    let mut with_examples = 0;
    for (page, text) in all_pages() {
        let runs = PAGES.contains(&page.as_str()) || page == GRADING_PAGE;
        if text.lines().any(|line| line.starts_with("```console")) {
            with_examples += 1;
            assert!(
                runs,
                "{page} has console examples but is not in tests/docs.rs's PAGES"
            );
        }
        assert!(
            !text.contains("```console,ignore"),
            "{page}: an example that does not run"
        );
        for (first, language, lines) in blocks(&text) {
            for (k, line) in lines.iter().enumerate() {
                let number = first + k;
                if language != "console" {
                    assert!(
                        !line.starts_with("$ "),
                        "{page}:{number}: a command example in a ```{language} block, which is \
                         not run: make it a ```console block with its output"
                    );
                } else if let Some(command) = line.strip_prefix("$ ") {
                    let program = command.split_whitespace().next().unwrap_or("");
                    assert!(
                        programs.contains(&program),
                        "{page}:{number}: `{program}` is not among the programs tests/docs.rs \
                         gives trycmd ({programs:?}), which would skip the example"
                    );
                }
            }
        }
    }
    assert!(
        with_examples >= 3,
        "only {with_examples} pages have console examples"
    );
}

/// The Makefile's targets: each line `name:` (or `a b:`) that is not a
/// variable's assignment.
fn make_targets() -> Vec<String> {
    let makefile = std::fs::read_to_string(repo().join("Makefile")).expect("Makefile");
    makefile
        .lines()
        .filter(|line| !line.starts_with(['\t', '#', ' ', '.']))
        .filter_map(|line| line.split_once(':'))
        .filter(|(_, rest)| !rest.starts_with('='))
        .flat_map(|(names, _)| names.split_whitespace().map(str::to_string))
        .collect()
}

/// A shell recipe (a ```` ```sh ```` block: a pipeline, a loop, a job
/// script) cannot run under trycmd, so none is left unrun in silence:
/// each `make TARGET` line names a target of the Makefile, and a block
/// with any other command sits in a section (from its heading to the next)
/// that names the test running it, `tests/NAME.rs`, a file that names the
/// page back, or says that no test runs it ("No test runs …", with the
/// reason).
#[test]
fn every_recipe_says_which_test_runs_it() {
    let targets = make_targets();
    assert!(targets.iter().any(|t| t == "test"), "{targets:?}");
    let mut recipes = 0;
    for (page, text) in all_pages() {
        // The page's sections: the text from each heading to the next, by
        // the line each starts on.
        let mut sections: Vec<(usize, String)> = vec![(1, String::new())];
        let mut fenced = false;
        for (number, line) in text.lines().enumerate() {
            if line.starts_with("```") {
                fenced = !fenced;
            }
            if !fenced && line.starts_with('#') {
                sections.push((number + 1, String::new()));
            }
            let section = &mut sections.last_mut().expect("a section").1;
            section.push_str(line);
            section.push('\n');
        }
        for (first, language, lines) in blocks(&text) {
            if language != "sh" {
                continue;
            }
            recipes += 1;
            let commands: Vec<&str> = lines
                .iter()
                .map(|line| line.trim())
                .filter(|line| !line.is_empty() && !line.starts_with('#'))
                .collect();
            for line in &commands {
                if let Some(target) = line.strip_prefix("make ") {
                    let target = target.split_whitespace().next().unwrap_or("");
                    assert!(
                        targets.iter().any(|t| t == target),
                        "{page}:{first}: `make {target}` is not a target of the Makefile"
                    );
                }
            }
            if commands.iter().all(|line| line.starts_with("make ")) {
                continue;
            }
            let section = &sections
                .iter()
                .rev()
                .find(|(start, _)| *start < first)
                .expect("a section")
                .1;
            let words: Vec<String> = section.split_whitespace().map(str::to_lowercase).collect();
            let says_none = words.join(" ").contains("no test runs");
            let runner = section
                .split(|c: char| c.is_whitespace() || matches!(c, '`' | '(' | ')' | ',' | ';'))
                .filter(|word| word.starts_with("tests/") && word.ends_with(".rs"))
                .find(|test| {
                    std::fs::read_to_string(repo().join(test))
                        .is_ok_and(|source| source.contains(page.as_str()))
                });
            assert!(
                says_none || runner.is_some(),
                "{page}:{first}: a shell recipe that no test is said to run: name the \
                 test that runs it as written (tests/NAME.rs, which reads {page}) in its \
                 section, or say \"No test runs\" it and why"
            );
        }
    }
    assert!(recipes >= 10, "only {recipes} shell recipes");
}

/// docs/README.md, the index, links every page of docs/ (its folders'
/// too, such as docs/diagnostics/), and README.md links the index.
#[test]
fn the_index_links_every_page() {
    let index = std::fs::read_to_string(repo().join("docs/README.md")).expect("docs/README.md");
    let mut pages = 0;
    for (page, _) in all_pages() {
        let Some(name) = page.strip_prefix("docs/") else {
            continue;
        };
        if name != "README.md" {
            pages += 1;
            assert!(
                index.contains(&format!("]({name})")),
                "docs/README.md does not link {name}"
            );
        }
    }
    assert!(pages >= 15, "only {pages} pages in docs/");
    let readme = std::fs::read_to_string(repo().join("README.md")).expect("README.md");
    assert!(
        readme.contains("](docs/README.md)"),
        "README.md does not link the index"
    );
}

/// GitHub's anchor of a heading: lowercase, punctuation but `-` and `_`
/// dropped, spaces as `-`.
fn anchor(heading: &str) -> String {
    heading
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | ' '))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The anchors of a page's headings (outside code blocks).
fn anchors(text: &str) -> Vec<String> {
    let mut fenced = false;
    let mut found = Vec::new();
    for line in text.lines() {
        if line.starts_with("```") {
            fenced = !fenced;
        } else if !fenced && line.starts_with('#') {
            let heading = line.trim_start_matches('#');
            if let Some(heading) = heading.strip_prefix(' ') {
                found.push(anchor(heading));
            }
        }
    }
    found
}

/// Every relative link of README.md and docs/ (outside code blocks) names
/// a file that exists, and a link into a page with `#anchor` names one of
/// its headings: pages split or sections renamed leave no link behind.
#[test]
fn every_link_names_a_page_and_heading_that_exist() {
    let pages = all_pages();
    let mut links = 0;
    for (page, text) in &pages {
        let folder = Path::new(page).parent().expect("a folder");
        let mut fenced = false;
        for line in text.lines() {
            if line.starts_with("```") {
                fenced = !fenced;
                continue;
            }
            if fenced {
                continue;
            }
            for (at, _) in line.match_indices("](") {
                let rest = &line[at + 2..];
                let Some(end) = rest.find(')') else { continue };
                let link = &rest[..end];
                if link.contains("://") || link.starts_with("mailto:") || link.contains(' ') {
                    continue;
                }
                links += 1;
                let (path, fragment) = link.split_once('#').unwrap_or((link, ""));
                let target = if path.is_empty() {
                    PathBuf::from(page)
                } else {
                    folder.join(path)
                };
                let on_disk = repo().join(&target);
                assert!(on_disk.exists(), "{page}: `{link}` names no file");
                if fragment.is_empty() || on_disk.extension().is_none_or(|e| e != "md") {
                    continue;
                }
                let target_text = std::fs::read_to_string(&on_disk).expect("read page");
                assert!(
                    anchors(&target_text).iter().any(|a| a == fragment),
                    "{page}: `{link}` names no heading of {}",
                    target.display()
                );
            }
        }
    }
    assert!(links >= 100, "only {links} links");
}
