//! The clean-up a Ctrl-C handler runs ([`output::abandon`]) against writes
//! in flight, and writes that fail half-way (a full disk). In its own test
//! binary, because `abandon` is for good: nothing is renamed after it in
//! this process.

mod support;

use std::io::{Error, ErrorKind};

use raytracer_render::output;
use support::listing;

#[test]
fn interrupted_and_failed_writes_leave_the_old_file_and_no_temporary() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.ppm");
    std::fs::write(&out, "old").unwrap();

    // A write that fails half-way, as on a full disk.
    let full = output::write_atomically(&out, |w| {
        w.write_all(&[0; 10_000])?;
        Err(Error::from_raw_os_error(28))
    });
    assert_eq!(full.unwrap_err().raw_os_error(), Some(28));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "old");
    assert_eq!(listing(dir.path()), ["out.ppm"]);

    // Ctrl-C half-way through a write: the handler's `abandon` removes the
    // temporary file, and the write cannot rename it afterwards.
    let interrupted = output::write_atomically(&out, |w| {
        w.write_all(b"new, but only half")?;
        w.flush()?;
        assert_eq!(listing(dir.path()).len(), 2, "a temporary file is written");
        assert_eq!(output::abandon(), 1);
        assert_eq!(listing(dir.path()), ["out.ppm"]);
        w.write_all(b" of it")
    });
    assert_eq!(interrupted.unwrap_err().kind(), ErrorKind::Interrupted);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "old");
    assert_eq!(listing(dir.path()), ["out.ppm"]);

    // After `abandon` nothing more is written.
    let after = output::write_atomically(&out, |w| w.write_all(b"late"));
    assert_eq!(after.unwrap_err().kind(), ErrorKind::Interrupted);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "old");
    assert_eq!(listing(dir.path()), ["out.ppm"]);
}
