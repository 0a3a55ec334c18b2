//! Helpers shared by stfit's tests (not published):
//!
//! - [`shared_file`]: a file of the shared folder beside the project (`$STFIT_SHARED`, else
//!   `../shared`), or `None` with one line saying the test did not run for want of it; under
//!   `CI=true` a missing file fails the test instead;
//! - [`Cli`]: runs the `stfit` binary with arguments and standard input;
//! - [`CaseDir`]: a temporary folder for one test's files, removed when dropped.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicU64, Ordering};

/// The shared folder: `$STFIT_SHARED`, else `shared` beside the project's root.
pub fn shared_dir() -> PathBuf {
    match std::env::var_os("STFIT_SHARED") {
        Some(p) => PathBuf::from(p),
        None => project_root().join("../shared"),
    }
}

/// The project's root folder (the workspace root).
pub fn project_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Whether the tests run under CI (`CI=true`), where data that should be there must be.
pub fn under_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

/// The file `relative` of the shared folder, or `None` when it is absent: then one line on
/// stderr says that `test` did not run for want of it (the caller returns and passes). Under
/// `CI=true` an absent file is a failure (a panic naming it).
pub fn shared_file(test: &str, relative: &str) -> Option<PathBuf> {
    let path = shared_dir().join(relative);
    if path.is_file() {
        return Some(path);
    }
    assert!(
        !under_ci(),
        "{test}: {} is missing, and under CI=true the shared folder is required \
         (set STFIT_SHARED or put the shared folder beside the project)",
        path.display()
    );
    eprintln!(
        "{test}: did not run for want of {} (set STFIT_SHARED to the shared folder)",
        path.display()
    );
    None
}

/// The Walter et al. 2007 measurements of the shared folder, as [`shared_file`].
pub fn walter_measurements(test: &str) -> Option<PathBuf> {
    shared_file(test, "data/walter2007/measurements.csv")
}

/// What a run of the binary gave.
#[derive(Debug, Clone)]
pub struct Run {
    /// The exit code (`None` if killed by a signal).
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
}

impl Run {
    /// Panics with the run's output unless it exited with code 0; returns stdout.
    pub fn ok(&self) -> &str {
        assert_eq!(
            self.code,
            Some(0),
            "exit {:?}\nstdout:\n{}\nstderr:\n{}",
            self.code,
            self.stdout,
            self.stderr
        );
        &self.stdout
    }

    /// Panics unless the run failed with `code`, printed nothing on stdout and did not panic;
    /// returns stderr.
    pub fn fails_with(&self, code: i32) -> &str {
        assert_eq!(self.code, Some(code), "stderr: {}", self.stderr);
        assert!(!self.stderr.contains("panicked"), "panic: {}", self.stderr);
        assert!(self.stdout.is_empty(), "stdout: {}", self.stdout);
        &self.stderr
    }
}

/// The `stfit` command line under test.
#[derive(Debug, Clone)]
pub struct Cli {
    bin: PathBuf,
}

impl Cli {
    /// The binary at `bin` (in an integration test of the `stfit` package:
    /// `Cli::new(env!("CARGO_BIN_EXE_stfit"))`).
    pub fn new(bin: impl Into<PathBuf>) -> Self {
        Self { bin: bin.into() }
    }

    /// Runs the binary with `args` and empty standard input.
    pub fn run(&self, args: &[&str]) -> Run {
        self.run_with_stdin(args, "")
    }

    /// Runs the binary with `args`, writing `stdin` to its standard input.
    pub fn run_with_stdin(&self, args: &[&str], stdin: &str) -> Run {
        let mut child = Command::new(&self.bin)
            .args(args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the stfit binary starts");
        let mut input = child.stdin.take().expect("piped stdin");
        let text = stdin.to_owned();
        // Written from a thread, so a large input cannot deadlock against a full output pipe.
        let writer = std::thread::spawn(move || {
            let _ = input.write_all(text.as_bytes());
        });
        let out = child.wait_with_output().expect("the stfit binary runs");
        writer.join().expect("the stdin writer");
        Run {
            code: out.status.code(),
            stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
            stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        }
    }

    /// The first line of standard error (with its line break) of the binary run with `args`,
    /// then stopped; `None` if no line comes within `timeout`. For a run too long to wait for,
    /// such as one that should announce its length before it starts.
    pub fn first_stderr_line(&self, args: &[&str], timeout: std::time::Duration) -> Option<String> {
        use std::io::{BufRead, BufReader};
        let mut child = Command::new(&self.bin)
            .args(args)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the stfit binary starts");
        let stderr = child.stderr.take().expect("piped stderr");
        let (send, receive) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let mut line = String::new();
            let _ = BufReader::new(stderr).read_line(&mut line);
            let _ = send.send(line);
        });
        let line = receive.recv_timeout(timeout).ok();
        let _ = child.kill();
        let _ = child.wait();
        line.filter(|l| !l.is_empty())
    }
}

/// A temporary folder for one test case, removed with its contents when dropped.
#[derive(Debug)]
pub struct CaseDir {
    dir: PathBuf,
}

impl CaseDir {
    /// A new empty folder whose name contains `name`, unique to this process and call.
    pub fn new(name: &str) -> Self {
        static NEXT: AtomicU64 = AtomicU64::new(0);
        let n = NEXT.fetch_add(1, Ordering::Relaxed);
        let dir =
            std::env::temp_dir().join(format!("stfit-test-{}-{n}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("a temporary folder");
        Self { dir }
    }

    /// The folder itself.
    pub fn path(&self) -> &Path {
        &self.dir
    }

    /// The path of `name` inside the folder (not created).
    pub fn join(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// Writes `contents` to `name` inside the folder and returns its path.
    pub fn file(&self, name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
        let path = self.join(name);
        std::fs::write(&path, contents).expect("a test file is written");
        path
    }
}

impl Drop for CaseDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// Radiance's binaries and library of the pyradiance package that `.ci/python-env` installs
/// under the build folder (`target/python-env`, or `$CARGO_TARGET_DIR/python-env`).
#[derive(Debug, Clone)]
pub struct Radiance {
    /// The folder of `pabopto2bsdf`, `bsdf2klems`, `checkBSDF`, ...
    pub bin: PathBuf,
    /// Radiance's library folder (for `RAYPATH`).
    pub lib: PathBuf,
    /// The Python interpreter of the environment, and the folder to put on `PYTHONPATH` (the
    /// one holding the `pyradiance` package) for `import pyradiance` to work.
    python: (PathBuf, PathBuf),
}

impl Radiance {
    /// A command running the Radiance program `name`, with the package's folders on `PATH`
    /// and `RAYPATH` (some programs call others and read templates from the library).
    pub fn command(&self, name: &str) -> Command {
        let mut cmd = Command::new(self.bin.join(name));
        let path = std::env::var_os("PATH").unwrap_or_default();
        let mut paths = vec![self.bin.clone()];
        paths.extend(std::env::split_paths(&path));
        cmd.env("PATH", std::env::join_paths(paths).expect("a valid PATH"));
        cmd.env("RAYPATH", format!(".:{}", self.lib.display()));
        cmd
    }

    /// A Python command that can `import pyradiance` (whose `pyradiance.bsdf` module is
    /// Radiance's BSDF library: `bsdf.load_file`, `bsdf.query`, ...).
    pub fn python(&self) -> Command {
        let (python, site) = &self.python;
        let mut cmd = Command::new(python);
        cmd.env("PYTHONPATH", site);
        cmd
    }
}

/// Radiance from `.ci/python-env`'s environment, or `None` with one line saying `test` did
/// not run for want of it; under `CI=true` its absence is a failure.
pub fn radiance(test: &str) -> Option<Radiance> {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| project_root().join("target"));
    let env = target.join("python-env");
    // A virtual environment (lib/pythonX.Y/site-packages) or, where venv is unavailable,
    // `pip install --target site` (.ci/python-env).
    let venv = std::fs::read_dir(env.join("lib"))
        .into_iter()
        .flatten()
        .filter_map(Result::ok)
        .map(|d| d.path().join("site-packages/pyradiance"));
    let found = venv
        .chain([env.join("site/pyradiance")])
        .find(|p| p.join("bin/pabopto2bsdf").is_file() && p.join("bin/checkBSDF").is_file());
    match found {
        Some(p) => {
            let site = p
                .parent()
                .expect("pyradiance's folder has a parent")
                .to_path_buf();
            // The virtual environment's own interpreter, else (`pip install --target`) the
            // Python 3 that installed it.
            let venv_python = env.join("bin/python");
            let python = if venv_python.is_file() {
                venv_python
            } else {
                PathBuf::from("python3")
            };
            Some(Radiance {
                bin: p.join("bin"),
                lib: p.join("lib"),
                python: (python, site),
            })
        }
        None => {
            assert!(
                !under_ci(),
                "{test}: under CI=true Radiance (pyradiance) is required in {}; run .ci/python-env",
                env.display()
            );
            eprintln!(
                "{test}: did not run for want of Radiance in {} (run .ci/python-env)",
                env.display()
            );
            None
        }
    }
}
