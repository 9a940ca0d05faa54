//! The processes of a run, from `/proc`: the parent and process group
//! of each, and the tree of processes descended from a run's first, for
//! the run to kill ([`crate::run`]) and its quota to find the files they
//! hold ([`crate::quota`]).

/// `leader` and every process descended from it now, from `/proc`.
pub(crate) fn descendants(leader: libc::pid_t) -> Vec<libc::pid_t> {
    let parents: Vec<(libc::pid_t, libc::pid_t)> = processes()
        .filter_map(|pid| Some((pid, parent_and_group(pid)?.0)))
        .collect();
    let mut tree = vec![leader];
    let mut next = 0;
    while let Some(&parent) = tree.get(next) {
        tree.extend(
            parents
                .iter()
                .filter(|&&(_, of)| of == parent)
                .map(|&(pid, _)| pid),
        );
        next += 1;
    }
    tree
}

/// The pids of `/proc`, in its order.
pub(crate) fn processes() -> impl Iterator<Item = libc::pid_t> {
    std::fs::read_dir("/proc")
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|entry| entry.file_name().to_str()?.parse().ok())
}

/// The parent and process group of `pid`, from `/proc/PID/stat`.
pub(crate) fn parent_and_group(pid: i32) -> Option<(i32, i32)> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The command name may hold spaces and parentheses: fields follow the last `)`.
    let rest = &stat[stat.rfind(')')? + 2..];
    let mut fields = rest.split(' ').skip(1);
    let parent = fields.next()?.parse().ok()?;
    let group = fields.next()?.parse().ok()?;
    Some((parent, group))
}
