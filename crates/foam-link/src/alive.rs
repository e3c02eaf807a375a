//! Whether a solver process still runs (Linux `/proc`): the coupler checks the pids of the
//! handshake while it waits, so a solver that dies never leaves it hanging.

/// True while process `pid` exists and is neither a zombie nor dead (`/proc/<pid>/stat`
/// state `Z` or `X`).
pub fn is_alive(pid: u32) -> bool {
    let Ok(stat) = std::fs::read_to_string(format!("/proc/{pid}/stat")) else {
        return false;
    };
    // "pid (comm) S ...": the state follows the last ')' (comm may hold spaces and parens).
    let state = stat
        .rsplit_once(')')
        .and_then(|(_, rest)| rest.trim_start().chars().next());
    !matches!(state, None | Some('Z') | Some('X'))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::process::Command;

    #[test]
    fn a_running_process_is_alive_and_an_exited_one_is_not() {
        assert!(is_alive(std::process::id()));
        let mut child = Command::new("sleep").arg("0.05").spawn().unwrap();
        let pid = child.id();
        assert!(is_alive(pid));
        // Not yet reaped: a zombie once it has exited.
        let t = std::time::Instant::now();
        while is_alive(pid) {
            assert!(
                t.elapsed().as_secs() < 10,
                "sleep 0.05 still alive after 10 s"
            );
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        child.wait().unwrap();
        assert!(!is_alive(pid));
    }
}
