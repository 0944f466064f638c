use clap::Parser;

fn main() {
    give_the_vulkan_loader_a_runtime_dir();
    std::process::exit(tumble::cli::main_with(tumble::cli::Cli::parse()));
}

/// Mesa's Vulkan drivers print "error: XDG_RUNTIME_DIR is invalid or not set" on every device
/// they open when the variable is unset (batch jobs, containers, ssh without a login session),
/// though nothing is wrong: such a process gets the user's private directory for it in the
/// temporary folder, as a login session would have one.
fn give_the_vulkan_loader_a_runtime_dir() {
    #[cfg(unix)]
    {
        use std::os::unix::fs::{DirBuilderExt, MetadataExt};
        if std::env::var_os("XDG_RUNTIME_DIR").is_some() {
            return;
        }
        let Ok(uid) = std::fs::metadata("/proc/self").map(|m| m.uid()) else { return };
        let dir = std::env::temp_dir().join(format!("tumble-runtime-{uid}"));
        let _ = std::fs::DirBuilder::new().mode(0o700).create(&dir);
        // Only a directory of this user's, which no one else may enter.
        let owned = std::fs::symlink_metadata(&dir).is_ok_and(|m| m.is_dir() && m.uid() == uid && m.mode() & 0o077 == 0);
        if !owned {
            return;
        }
        // SAFETY: the first thing main does, before any thread exists or any library reads the
        // environment.
        unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
    }
}
