//! Watching the scene and its textures through the platform's file
//! notifications ([`notify`]).
//!
//! The folders are watched, not the files: editors save by writing a new
//! file and renaming it over the old one (which a watch on the old file
//! would miss), and a deleted scene must be seen coming back. Of the
//! events in those folders, only changes (not reads) to the scene, to a
//! texture of its last good version, or to any image file count, the last
//! for a texture that a scene with errors names but that does not exist
//! yet. Each counted event sends `()` on the channel; the caller waits
//! for a pause before rebuilding.

use std::collections::BTreeSet;
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::sync::mpsc::Sender;
use std::sync::{Arc, Mutex};

use notify::event::{MetadataKind, ModifyKind};
use notify::{Event, EventKind, RecommendedWatcher, RecursiveMode, Watcher};

/// The extensions of the image files a texture can be (docs/language.md).
const IMAGE_EXTENSIONS: [&str; 4] = ["ppm", "png", "jpg", "jpeg"];

/// The folders watched and the file names that count in them.
pub struct Watch {
    watcher: RecommendedWatcher,
    folders: BTreeSet<PathBuf>,
    names: Arc<Mutex<BTreeSet<OsString>>>,
}

impl Watch {
    /// Watch `scene`'s folder, sending `()` on `changed` for each change
    /// that counts.
    pub fn new(scene: &Path, changed: Sender<()>) -> notify::Result<Watch> {
        let names = Arc::new(Mutex::new(BTreeSet::new()));
        let counted = names.clone();
        let watcher = notify::recommended_watcher(move |event: notify::Result<Event>| {
            let Ok(event) = event else { return };
            let names = counted.lock().unwrap_or_else(|e| e.into_inner());
            if counts(&event, &names) {
                let _ = changed.send(());
            }
        })?;
        let mut watch = Watch {
            watcher,
            folders: BTreeSet::new(),
            names,
        };
        watch.add(scene)?;
        Ok(watch)
    }

    /// Also watch these textures (a folder that cannot be watched, such as
    /// one that does not exist, is left out: the scene's errors say why).
    pub fn add_textures(&mut self, textures: &[PathBuf]) {
        for texture in textures {
            let _ = self.add(texture);
        }
    }

    /// Watch `file`'s folder and count changes to its name.
    fn add(&mut self, file: &Path) -> notify::Result<()> {
        let folder = folder_of(file);
        if !self.folders.contains(&folder) {
            self.watcher.watch(&folder, RecursiveMode::NonRecursive)?;
            self.folders.insert(folder);
        }
        if let Some(name) = file.file_name() {
            let mut names = self.names.lock().unwrap_or_else(|e| e.into_inner());
            names.insert(name.to_os_string());
        }
        Ok(())
    }
}

/// Whether `event` changes a file that counts: one of `names` or an image.
fn counts(event: &Event, names: &BTreeSet<OsString>) -> bool {
    let changes = match event.kind {
        EventKind::Create(_) | EventKind::Remove(_) | EventKind::Any | EventKind::Other => true,
        EventKind::Modify(ModifyKind::Metadata(MetadataKind::AccessTime)) => false,
        EventKind::Modify(_) => true,
        EventKind::Access(_) => false,
    };
    changes
        && event.paths.iter().any(|path| {
            path.file_name().is_some_and(|name| names.contains(name))
                || path.extension().is_some_and(|extension| {
                    IMAGE_EXTENSIONS
                        .iter()
                        .any(|image| extension.eq_ignore_ascii_case(image))
                })
        })
}

/// The folder `file` is in (`.` for a bare name).
fn folder_of(file: &Path) -> PathBuf {
    raytracer_scene::folder::folder_of(file).to_path_buf()
}

#[cfg(test)]
mod tests {
    use super::*;
    use notify::event::{AccessKind, CreateKind, DataChange};

    fn event(kind: EventKind, path: &str) -> Event {
        Event::new(kind).add_path(PathBuf::from(path))
    }

    #[test]
    fn changes_to_the_scene_and_images_count_and_reads_do_not() {
        let names = BTreeSet::from([OsString::from("scene.txt")]);
        let write = EventKind::Modify(ModifyKind::Data(DataChange::Any));
        assert!(counts(&event(write, "dir/scene.txt"), &names));
        assert!(counts(
            &event(EventKind::Create(CreateKind::File), "dir/wood.PPM"),
            &names
        ));
        assert!(!counts(&event(write, "dir/.scene.txt.swp"), &names));
        assert!(!counts(
            &event(EventKind::Access(AccessKind::Any), "dir/scene.txt"),
            &names
        ));
    }

    #[test]
    fn a_bare_name_is_in_the_working_folder() {
        assert_eq!(folder_of(Path::new("scene.txt")), PathBuf::from("."));
        assert_eq!(folder_of(Path::new("a/b.txt")), PathBuf::from("a"));
    }
}
