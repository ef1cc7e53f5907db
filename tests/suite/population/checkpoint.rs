//! A run killed (SIGKILL, no chance to clean up) and resumed, twice, ends with bitwise the
//! records of an uninterrupted run. The child is this test binary itself, running the ignored
//! test `child_run` (its full path in the suite, `--exact`) with the checkpoint folder in an
//! environment variable.

use super::common as population_common;

use population_common::{Faulty, FaultySoftPipe, config, integrator, plan, soft_pipe};
use pseudorigid::population::{Case, Progress, RunOptions, RunOutput, Shard, run};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Where the child keeps its checkpoint; unset: not a child.
const DIR_VAR: &str = "PSEUDORIGID_POPULATION_CHILD_DIR";
const PARTICLES: u64 = 60;
/// The child's test, by its path in the suite (`module_path!()` without the crate's name).
const CHILD_TEST: &str = "population::checkpoint::child_run";

/// Every particle's draw sleeps this long in the child, so the run lasts ≥ 60 × 40 ms = 2.4 s and
/// the parent can kill it mid-run.
const DELAY: Duration = Duration::from_millis(40);

fn output_path(dir: &Path) -> PathBuf {
    dir.join("final.json")
}

/// Checkpoint chunks and the records they hold.
fn checkpointed(dir: &Path) -> (usize, usize) {
    let mut chunks = 0;
    let mut records = 0;
    for entry in std::fs::read_dir(dir.join("checkpoint"))
        .into_iter()
        .flatten()
        .flatten()
    {
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.starts_with("chunk-") {
            chunks += 1;
            // Chunks are gzipped JSON.
            let mut text = String::new();
            let file = std::fs::File::open(entry.path()).unwrap();
            std::io::Read::read_to_string(&mut flate2::read::GzDecoder::new(file), &mut text).unwrap();
            let value: serde_json::Value = serde_json::from_str(&text).unwrap();
            records += value["records"].as_array().unwrap().len();
        }
    }
    (chunks, records)
}

/// The child: run (resuming whatever checkpoint there is) serially with slow draws and a
/// checkpoint every 50 ms, then write the final output.
#[test]
#[ignore = "child process of killed_run_resumes_bitwise"]
fn child_run() {
    // Not a test by itself: under `--include-ignored` without the parent there is nothing to do.
    let Some(dir) = std::env::var_os(DIR_VAR).map(PathBuf::from) else {
        return;
    };
    let (stokes, pipe) = (integrator(), soft_pipe());
    let slow = Faulty {
        inner: pipe.clone(),
        delay: Some(DELAY),
    };
    let case = Case::new(&stokes, pipe.flow(), pipe.boundary(), &slow, plan());
    let options = RunOptions::default()
        .serial()
        .with_progress(Progress::Auto)
        .with_checkpoints(dir.join("checkpoint"), Duration::from_millis(50))
        .resume(true);
    let out = run(&case, &config(PARTICLES), Shard::ALL, &options).unwrap();
    out.write_json(output_path(&dir)).unwrap();
}

fn child(dir: &Path) -> Command {
    let mut command = Command::new(std::env::current_exe().unwrap());
    let _ = command
        .args(["--exact", CHILD_TEST, "--ignored", "--nocapture", "--test-threads", "1"])
        .env(DIR_VAR, dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    command
}

fn spawn_child(dir: &Path) -> Child {
    child(dir).stderr(Stdio::null()).spawn().unwrap()
}

/// Wait until `ready` holds (polling every 2 ms, at most a minute), then kill the child.
fn kill_when(mut child: Child, ready: impl Fn() -> bool) {
    let start = Instant::now();
    while !ready() {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "the child made no progress in a minute"
        );
        assert!(
            child.try_wait().unwrap().is_none(),
            "the child ended before it was killed"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    child.kill().unwrap();
    let status = child.wait().unwrap();
    assert!(!status.success(), "the child was not killed: {status}");
}

#[test]
fn killed_run_resumes_bitwise() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("population-kill");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();

    // Kill 1: right after the first checkpoint chunk.
    kill_when(spawn_child(&dir), || checkpointed(&dir).0 >= 1);
    let (_, after_first) = checkpointed(&dir);
    // Kill 2: the resumed child, once it has added records of its own (so it did resume and
    // write), killed at whatever instant that is: mid-particle, mid-sleep or mid-write.
    kill_when(spawn_child(&dir), || checkpointed(&dir).1 > after_first);
    let (_, after_second) = checkpointed(&dir);
    assert!(!output_path(&dir).exists(), "a killed child wrote its final output");
    assert!(
        after_first >= 1 && after_second > after_first && (after_second as u64) < PARTICLES,
        "records checkpointed: {after_first} then {after_second} of {PARTICLES}"
    );

    // Resume to the end in a third child, and compare with an uninterrupted run in-process.
    let done = child(&dir).output().unwrap();
    let log = String::from_utf8_lossy(&done.stderr);
    assert!(done.status.success(), "resumed child: {}\n{log}", done.status);
    // Its stderr is a pipe, not a terminal: progress comes as plain log lines, the last one
    // at the end of the run.
    assert!(
        log.lines()
            .any(|l| l.starts_with("population shard 0/1: 60/60 particles (100.0 %)") && l.ends_with("ETA 0s")),
        "{log}"
    );
    let resumed = RunOutput::<pseudorigid::material::NeoHooke>::read_json(output_path(&dir)).unwrap();
    let soft = FaultySoftPipe::new();
    let case = soft.case(plan());
    let whole = run(&case, &config(PARTICLES), Shard::ALL, &RunOptions::default().quiet()).unwrap();
    assert!(resumed.to_json().unwrap() == whole.to_json().unwrap());
    // No temporary file of a killed write is taken for a chunk, and none is left after the
    // writes of the last child (write_atomic removes leftovers of dead processes).
    let leftovers: Vec<_> = std::fs::read_dir(dir.join("checkpoint"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with("chunk-"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

/// 64-bit FNV-1a, as `build.rs` computes the source hash.
fn fnv1a(mut h: u64, bytes: &[u8]) -> u64 {
    for &b in bytes {
        h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The code version sealed into checkpoints and caches is the crate version plus the hash of
/// the sources this test binary was built from: recomputed here from `src/` (FNV-1a, checked
/// first against the published test vectors of Fowler, Noll & Vo), it matches, so the build
/// script reran on the last change of any source file, and a cache written before that change
/// cannot be taken for this code's.
#[test]
fn sealed_version_is_the_hash_of_the_sources() {
    const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    assert_eq!(fnv1a(OFFSET, b""), 0xcbf2_9ce4_8422_2325);
    assert_eq!(fnv1a(OFFSET, b"a"), 0xaf63_dc4c_8601_ec8c);
    assert_eq!(fnv1a(OFFSET, b"foobar"), 0x8594_4171_f739_67e8);
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut paths = Vec::new();
    let mut dirs = vec![src.clone()];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                dirs.push(path)
            } else {
                paths.push(path)
            }
        }
    }
    paths.sort();
    let mut h = OFFSET;
    for path in &paths {
        let relative = path.strip_prefix(&src).unwrap().to_string_lossy().replace('\\', "/");
        let bytes = std::fs::read(path).unwrap();
        for part in [relative.as_bytes(), bytes.as_slice()] {
            h = fnv1a(h, &(part.len() as u64).to_le_bytes());
            h = fnv1a(h, part);
        }
    }
    assert_eq!(
        pseudorigid::population::seal::VERSION,
        format!("{}+src.{h:016x}", env!("CARGO_PKG_VERSION"))
    );
}
