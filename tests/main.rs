//! The integration tests, as one test binary with a module per area (the
//! layout rust-analyzer and cargo use for large suites): every file in
//! `tests/` links the crate once, not once per file. `interrupt.rs` is the
//! one test with a binary of its own, because the clean-up it exercises
//! ([`raytracer_render::output::abandon`]) is for good in the process that runs it.

mod reference;
mod support;

mod accuracy_cli;
mod adaptive;
mod build_profile;
mod bvh_exact;
mod check_cli;
mod check_corpus;
mod check_formats;
mod check_rules;
mod cli;
mod compare_cli;
mod convert_cli;
mod distributed;
mod docs;
mod fix_never_worse;
mod format;
mod grade_browser;
mod grade_class;
mod grade_cli;
mod grade_disk;
mod grade_doc_tracers;
mod grade_sandbox;
mod grade_students;
mod grade_suite_format;
mod gradescope;
mod hostile_inputs;
mod hostile_text;
mod install;
mod intersection;
mod language_table;
mod lsp;
mod neovim;
mod no_panic;
mod pov;
mod preview;
mod preview_browser;
mod reference_model;
mod registry;
mod render_cli;
mod round_trip;
mod semantic_tokens;
mod slurm;
mod stability;
mod texture_headers;
mod textures;
mod tidy;
mod tile_cli;
mod ui;
mod version;
mod vim_syntax;
mod vscode;
