//! A sweep on a real Slurm cluster: the example job script submitted as a job array of four
//! tasks with `sbatch --wait`, the shards merged, the result compared with the unsharded run.
//! Ignored in a plain `cargo test`; `./scripts/test` starts a one-node cluster
//! (scripts/slurm-cluster), exports its SLURM_CONF and runs it.

mod common;

use common::without_wall;

use std::path::PathBuf;
use std::process::Command;
use telescopic::Silent;
use telescopic::sweep::{Shard, Sweep, SweepOptions, read_table, run_sweep};

#[test]
#[ignore = "needs a running Slurm cluster: ./scripts/test starts one"]
fn a_job_array_sweep_merges_into_the_unsharded_file() {
    let conf = std::env::var("SLURM_CONF").unwrap_or_default();
    assert!(
        !conf.is_empty(),
        "SLURM_CONF is not set: this test needs the one-node cluster that ./scripts/test starts"
    );
    let sinfo = Command::new("sinfo").args(["-h", "-o", "%T"]).output();
    let state = sinfo
        .as_ref()
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned());
    assert!(
        state.as_deref().is_ok_and(|s| s
            .lines()
            .any(|l| l == "idle" || l == "mixed" || l == "allocated")),
        "the Slurm cluster of {conf} is not up (sinfo: {sinfo:?})"
    );
    let root = PathBuf::from(common::ROOT);
    let dir = std::env::temp_dir().join(format!("telescopic-slurm-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let sweep_path = dir.join("study.toml");
    std::fs::write(
        &sweep_path,
        format!(
            "scene = {:?}\nset = [\"time.end=1.0\"]\n[grid]\n\"contact.clearance\" = [0.0, 0.005, 0.01]\n\
             \"masses.load\" = [10.0, 20.0, 30.0]\n\"drive.force\" = [50.0, 100.0]\n",
            root.join("scenes/adams-clearance.toml")
        ),
    )
    .unwrap();
    let whole = dir.join("whole.csv");
    let sweep = Sweep::load(&sweep_path).unwrap();
    run_sweep(
        &sweep,
        &SweepOptions {
            out: whole.clone(),
            jobs: 2,
            shard: Shard::whole(),
            resume: false,
            memory_budget: telescopic::run::memory::DEFAULT_MEMORY_BUDGET,
            cancel: Default::default(),
        },
        &Silent,
    )
    .unwrap();

    let submitted = Command::new("sbatch")
        .args(["--wait", "--array=0-3", "--chdir"])
        .arg(&dir)
        .arg(root.join("examples/slurm/sweep.sbatch"))
        .args(["study.toml", "results"])
        .env("TELESCOPIC", env!("CARGO_BIN_EXE_telescopic"))
        .output()
        .expect("sbatch runs");
    let said = String::from_utf8_lossy(&submitted.stdout);
    assert!(
        submitted.status.success(),
        "sbatch: {said}{}",
        String::from_utf8_lossy(&submitted.stderr)
    );
    let job = said
        .trim()
        .strip_prefix("Submitted batch job ")
        .unwrap_or_else(|| panic!("sbatch said {said:?}"));
    // every task ran under Slurm, as a task of this job array
    for task in 0..4 {
        let log = std::fs::read_to_string(dir.join(format!("telescopic-sweep-{job}_{task}.log")))
            .unwrap();
        assert!(
            log.contains(&format!("array task {task} of 4 (job {job})")),
            "{log}"
        );
        let shard = read_table(&dir.join(format!("results/shard-{task}.csv"))).unwrap();
        assert_eq!(
            shard.header_field("shard"),
            Some(format!("{task}/4").as_str())
        );
        assert!(shard.rows.iter().all(|(i, _)| i % 4 == task));
    }
    let merged = dir.join("merged.csv");
    let mut merge = Command::new(env!("CARGO_BIN_EXE_telescopic"));
    merge.arg("sweep-merge");
    for task in 0..4 {
        merge.arg(dir.join(format!("results/shard-{task}.csv")));
    }
    let out = merge.arg("--out").arg(&merged).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(without_wall(&merged), without_wall(&whole));
    assert_eq!(read_table(&merged).unwrap().rows.len(), 18);
    std::fs::remove_dir_all(&dir).unwrap();
}
