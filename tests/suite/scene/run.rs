//! The command as a user runs it: a run killed after its first checkpoint and resumed, and a
//! run split into two shards and merged, both give bitwise the files of an uninterrupted run.

use super::command::{BIN, chunks, ok, pseudorigid, results};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// 400 oblate particles injected on a disc in shear with random orientations, each run for
/// 5 time units: a few seconds on one thread, so a kill lands mid-run.
const SCENE: &str = r#"seed = 11
[flow]
type = "shear"
rate = 1.0
[fluid]
viscosity = 1.0
density = 1.0
[particles]
density = 1.0
[particles.inject]
count = 400
semi_axes = [0.6786044041487266, 0.27144176165949063, 0.6786044041487266]
random_orientation = true
region = { type = "disc", centre = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0], radius = 2.0 }
material = { law = "neo_hooke", mu = 2.5, lambda = 2500.0 }
[integrator]
type = "stokesian"
tol = 1e-8
dt = 1e-3
overdamped = true
[end]
t_end = 5.0
[output]
every = 1.0
"#;

fn workdir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
    dir
}

#[test]
fn killed_and_resumed_run_equals_uninterrupted_run() {
    let dir = workdir("cli_resume");
    ok(pseudorigid(&dir, &["run", "scene.toml", "--out", "whole", "--quiet"]));
    let whole = results(&dir.join("whole"));

    let mut child = Command::new(BIN)
        .current_dir(&dir)
        .args(["run", "scene.toml", "--out", "killed", "--quiet", "--threads", "1"])
        .args(["--checkpoint-every", "0.2"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let checkpoint = dir.join("killed").join("checkpoint-0000-of-0001");
    let started = Instant::now();
    // Bounded wait: the first chunk is due 0.2 s after the start.
    while chunks(&checkpoint) == 0 {
        assert!(
            started.elapsed() < Duration::from_secs(120),
            "no checkpoint after 120 s"
        );
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before its first checkpoint"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(
        !dir.join("killed").join("records.parquet").exists(),
        "the run finished before it was killed"
    );
    let kept = chunks(&checkpoint);

    // A new run must not write into the killed run's checkpoint.
    let refused = pseudorigid(&dir, &["run", "scene.toml", "--out", "killed", "--quiet"]);
    assert!(!refused.status.success());
    assert!(String::from_utf8_lossy(&refused.stderr).contains("resume"));

    ok(pseudorigid(
        &dir,
        &["run", "scene.toml", "--out", "killed", "--quiet", "--resume"],
    ));
    assert!(chunks(&checkpoint) > kept);
    assert_eq!(results(&dir.join("killed")), whole);
}

#[test]
fn merged_shards_equal_the_whole_run() {
    let dir = workdir("cli_shards");
    ok(pseudorigid(&dir, &["run", "scene.toml", "--out", "whole", "--quiet"]));
    for k in ["0/2", "1/2"] {
        ok(pseudorigid(
            &dir,
            &["run", "scene.toml", "--out", "sharded", "--quiet", "--shard", k],
        ));
    }
    let merged = ok(pseudorigid(&dir, &["merge", "scene.toml", "--out", "sharded"]));
    assert!(merged.contains("merged 400 particles"), "{merged}");
    assert_eq!(results(&dir.join("sharded")), results(&dir.join("whole")));

    // A changed scene is a different run: its merge refuses these shards.
    let other = SCENE.replace("seed = 11", "seed = 12");
    std::fs::write(dir.join("other.toml"), other).unwrap();
    let refused = pseudorigid(&dir, &["merge", "other.toml", "--out", "sharded"]);
    assert!(!refused.status.success());
    assert!(String::from_utf8_lossy(&refused.stderr).contains("different run"));
}
