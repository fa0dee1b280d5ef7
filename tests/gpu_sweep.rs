//! `scripts/gpu-sweep`, the GPU figures in one command, run with a stand-in for umbra (no GPU is
//! needed to check what it asks of one): it runs the full sweep and the many-lights sweep into one
//! folder and packs them, and it refuses a software adapter before running anything.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

/// A stand-in umbra in `dir` that names `adapter` when it renders, writes a file into each
/// bench's `--out` folder and logs its arguments, a line a call, to `calls.txt` beside it.
fn stand_in(dir: &Path, adapter: &str) -> PathBuf {
    let path = dir.join("umbra");
    let log = dir.join("calls.txt");
    let script = format!(
        "#!/usr/bin/env bash\n\
         echo \"$*\" >> '{log}'\n\
         case \"$1\" in\n\
         render) echo 'adapter: {adapter}' ;;\n\
         bench) while [ $# -gt 0 ]; do [ \"$1\" = --out ] && mkdir -p \"$2\" && echo row > \"$2/results.csv\"; shift; done ;;\n\
         esac\n",
        log = log.display()
    );
    std::fs::write(&path, script).unwrap();
    Command::new("chmod").arg("+x").arg(&path).status().unwrap();
    path
}

fn sweep(dir: &Path, umbra: &Path) -> std::process::Output {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/gpu-sweep");
    let out = dir.join("run");
    Command::new("bash").arg(script).arg("--umbra").arg(umbra).arg("--out").arg(out).output().unwrap()
}

#[test]
fn it_runs_both_sweeps_into_one_folder_and_packs_them() {
    let dir = common::scratch("gpu-sweep");
    let umbra = stand_in(&dir, "NVIDIA H100 (DiscreteGpu, Vulkan backend)");
    let run = sweep(&dir, &umbra);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let calls = std::fs::read_to_string(dir.join("calls.txt")).unwrap();
    let out = dir.join("run");
    let expected = [
        format!("bench --out {}", out.join("bench").display()),
        format!(
            "bench --lights --out {} --width 480 --height 270 --frames 5 --soft-rays 8",
            out.join("bench-lights").display()
        ),
    ];
    let benches: Vec<&str> = calls.lines().filter(|l| l.starts_with("bench")).collect();
    assert_eq!(benches, expected, "{calls}");
    assert_eq!(
        std::fs::read_to_string(out.join("adapter.txt")).unwrap().trim(),
        "NVIDIA H100 (DiscreteGpu, Vulkan backend)"
    );
    let times = std::fs::read_to_string(out.join("times.txt")).unwrap();
    assert!(times.contains("bench: ") && times.contains("bench-lights: "), "{times}");
    let listed = Command::new("tar").arg("-tzf").arg(dir.join("run.tar.gz")).output().unwrap();
    let listed = String::from_utf8_lossy(&listed.stdout);
    for file in ["run/bench/results.csv", "run/bench-lights/results.csv", "run/adapter.txt", "run/times.txt"] {
        assert!(listed.lines().any(|l| l.trim_start_matches("./") == file), "{file} not in the archive:\n{listed}");
    }
}

#[test]
fn it_refuses_a_software_adapter_and_an_unknown_argument_before_running_anything() {
    let dir = common::scratch("gpu-sweep-cpu");
    let umbra = stand_in(&dir, "llvmpipe (LLVM 15.0.6, 256 bits) (Cpu, Vulkan backend)");
    let run = sweep(&dir, &umbra);
    assert_eq!(run.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&run.stderr).contains("software rasterizer"));
    let calls = std::fs::read_to_string(dir.join("calls.txt")).unwrap();
    assert!(!calls.contains("bench"), "{calls}");
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/gpu-sweep");
    let odd = Command::new("bash").arg(&script).arg("--fast").output().unwrap();
    assert_eq!(odd.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&odd.stderr).contains("unknown argument '--fast'"));
    let missing = Command::new("bash").arg(&script).arg("--umbra").arg(dir.join("nothing")).output().unwrap();
    assert_eq!(missing.status.code(), Some(2));
}
