//! The folder a file is in, as a path that names it: `.` for a bare file
//! name, whose `Path::parent` is empty. Scenes, textures, outputs and
//! suites all resolve relative names from it.

use std::path::Path;

/// The folder `file` is in (`.` for a bare name or a root).
pub fn folder_of(file: &Path) -> &Path {
    match file.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => folder,
        _ => Path::new("."),
    }
}

#[cfg(test)]
mod tests {
    use super::folder_of;
    use std::path::Path;

    #[test]
    fn a_bare_name_is_in_the_current_folder() {
        assert_eq!(folder_of(Path::new("a.txt")), Path::new("."));
        assert_eq!(folder_of(Path::new("s/a.txt")), Path::new("s"));
        assert_eq!(folder_of(Path::new("/a.txt")), Path::new("/"));
        assert_eq!(folder_of(Path::new("/")), Path::new("."));
    }
}
