//! The Slurm scripts of `cases/bifurcation/slurm`, run against stand-ins for `sbatch` and
//! `srun` that log their arguments: the array and the merge job are submitted with the right
//! array range and an `afterok` dependency on the array's job id, and an array task runs the
//! program with rayon on the task's CPUs.

use std::path::{Path, PathBuf};
use std::process::Command;

fn scripts() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/bifurcation/slurm")
}

/// A folder with executable stand-ins: `sbatch` logs its arguments and prints a job id
/// (`4242;cluster` for an array, as `--parsable` does on a multi-cluster set-up, `4243`
/// otherwise); `srun` logs its arguments and the rayon thread count.
fn fake_slurm(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("slurm-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let log = dir.join("log");
    let sbatch = format!(
        "#!/bin/bash\necho \"sbatch $*\" >> {log:?}\nif [[ \"$*\" == *--array=* ]]; then echo '4242;cluster'; else echo 4243; fi\n"
    );
    let srun = format!("#!/bin/bash\necho \"srun RAYON_NUM_THREADS=$RAYON_NUM_THREADS $*\" >> {log:?}\n");
    for (file, text) in [("sbatch", sbatch), ("srun", srun)] {
        let path = dir.join(file);
        std::fs::write(&path, text).unwrap();
        let _ = Command::new("chmod").arg("+x").arg(&path).status().unwrap();
    }
    dir
}

fn with_path(dir: &Path) -> String {
    format!("{}:{}", dir.display(), std::env::var("PATH").unwrap_or_default())
}

#[test]
fn submit_wires_the_merge_to_the_array() {
    let dir = fake_slurm("submit");
    let out = Command::new("bash")
        .arg(scripts().join("submit.sh"))
        .args(["16", "prog run --stk 0.1 --out runs/a", "prog merge runs/a"])
        .env("PATH", with_path(&dir))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "array job 4242 (16 shards), merge job 4243\n"
    );
    let slurm = scripts();
    let log = std::fs::read_to_string(dir.join("log")).unwrap();
    assert_eq!(
        log,
        format!(
            "sbatch --parsable --array=0-15 {}/array.sbatch prog run --stk 0.1 --out runs/a\n\
             sbatch --parsable --dependency=afterok:4242 {}/merge.sbatch prog merge runs/a\n",
            slurm.display(),
            slurm.display()
        )
    );
    for bad in [vec!["0", "a", "b"], vec!["x", "a", "b"], vec!["2", "a"]] {
        let status = Command::new("bash")
            .arg(scripts().join("submit.sh"))
            .args(&bad)
            .env("PATH", with_path(&dir))
            .stderr(std::process::Stdio::null())
            .status()
            .unwrap();
        assert_eq!(status.code(), Some(2), "{bad:?}");
    }
}

#[test]
fn array_task_runs_the_program_on_its_cpus() {
    let dir = fake_slurm("array");
    let run = |vars: &[(&str, &str)]| {
        let mut c = Command::new("bash");
        let _ = c
            .arg(scripts().join("array.sbatch"))
            .args(["prog", "run", "--out", "runs/a"])
            .env("PATH", with_path(&dir))
            .env_remove("SLURM_ARRAY_TASK_ID")
            .env_remove("SLURM_ARRAY_TASK_COUNT")
            .env_remove("SLURM_ARRAY_TASK_MIN");
        for (k, v) in vars {
            let _ = c.env(k, v);
        }
        c.output().unwrap()
    };
    let out = run(&[
        ("SLURM_ARRAY_TASK_ID", "3"),
        ("SLURM_ARRAY_TASK_COUNT", "4"),
        ("SLURM_CPUS_PER_TASK", "8"),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("shard 3/4 on "));
    let log = std::fs::read_to_string(dir.join("log")).unwrap();
    assert_eq!(
        log,
        "srun RAYON_NUM_THREADS=8 --ntasks=1 --cpus-per-task=8 prog run --out runs/a\n"
    );
    // Outside a job array the script refuses to run.
    assert_eq!(run(&[]).status.code(), Some(2));
}
