//! Interrupted renders resume into the one-shot bytes: aborts after N
//! checkpointed tiles and in the middle of a checkpoint write (a test hook
//! of the binary, `STRATA_TEST_HOOK`), a real SIGINT and a real SIGKILL;
//! each leaves only its checkpoint, and the resumed render renders exactly
//! the tiles the checkpoint lacks. No verdict depends on time: a signal is
//! sent once the checkpoint holds a tile, and the render's further tiles
//! are held (not changed) until it comes.

use std::os::unix::process::ExitStatusExt;
use std::path::Path;
use std::process::{Command, Output, Stdio};

const HOOK: &str = "STRATA_TEST_HOOK";

/// A one-sphere scene file.
const SCENE: &str = "[camera]\nlook_from = [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, -1.0]\nvfov = \
                     60.0\n\n[materials.m]\nkind = \"lambertian\"\nalbedo = [0.5, 0.5, 0.5]\n\n\
                     [[spheres]]\ncenter = [0.0, 0.0, -3.0]\nradius = 1.0\nmaterial = \"m\"\n";

fn strata(dir: &Path, args: &[&str], hook: Option<&str>) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_strata"));
    c.args(args).current_dir(dir).env_remove(HOOK);
    if let Some(h) = hook {
        c.env(HOOK, h);
    }
    c.output().expect("the strata binary runs")
}

fn ok(dir: &Path, args: &[&str]) -> String {
    let out = strata(dir, args, None);
    assert!(
        out.status.success(),
        "strata {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn bytes(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// `resumed: K of T tiles from the checkpoint, R rendered now` → (K, T, R).
fn resumed_counts(stdout: &str) -> (usize, usize, usize) {
    let line = stdout
        .lines()
        .find(|l| l.starts_with("resumed: "))
        .unwrap_or_else(|| panic!("no `resumed:` line in {stdout}"));
    let n: Vec<usize> = line
        .split(|c: char| !c.is_ascii_digit())
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().unwrap())
        .collect();
    (n[0], n[1], n[2])
}

/// Tiles recorded whole in a checkpoint: the records after the header,
/// walked by their lengths (a torn last one is not counted).
fn recorded(path: &Path) -> usize {
    let b = bytes(path);
    let Some(head) = b.windows(2).position(|w| w == b"\n\n") else {
        return 0;
    };
    let mut at = head + 2;
    let mut n = 0;
    while at + 12 <= b.len() {
        let count = u32::from_le_bytes(b[at + 8..at + 12].try_into().unwrap()) as usize;
        let len = 44 + 64 * count;
        if at + len > b.len() {
            break;
        }
        at += len;
        n += 1;
    }
    n
}

/// Renders in one go with `--no-checkpoint`, then again interrupted by
/// each hook in turn (each run after the first resumes the last; `whole`
/// is the tiles the hook lets it record), and compares.
fn interrupted_runs_match_one_shot(render: &[&str], output: &str, hooks: &[(&str, usize)]) {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let one = format!("one-{output}");
    let mut args = render.to_vec();
    args.extend(["--no-checkpoint", "-o", &one]);
    ok(d, &args);
    let want = bytes(&d.join(&one));
    std::fs::remove_file(d.join(&one)).unwrap();
    let checkpoint = format!("{output}.checkpoint");
    let mut kept = 0;
    for (i, (hook, whole)) in hooks.iter().enumerate() {
        let mut args = render.to_vec();
        args.extend(["-o", output]);
        let resume = ["render", "--resume", &checkpoint];
        let run: &[&str] = if i == 0 { &args } else { &resume };
        let out = strata(d, run, Some(hook));
        assert_eq!(
            out.status.signal(),
            Some(6),
            "{hook}: the hook aborts: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(
            names(d),
            std::slice::from_ref(&checkpoint),
            "{hook}: only the checkpoint"
        );
        kept += whole;
        assert_eq!(recorded(&d.join(&checkpoint)), kept, "{hook}");
    }
    let out = ok(d, &["render", "--resume", &checkpoint]);
    let (k, t, r) = resumed_counts(&out);
    assert_eq!(k, kept, "every whole record is kept: {out}");
    assert_eq!(k + r, t, "no tile rendered twice: {out}");
    assert_eq!(names(d), [output.to_string()], "the checkpoint is removed");
    assert!(
        bytes(&d.join(output)) == want,
        "{render:?}: the resumed file differs from the one-shot"
    );
}

#[test]
fn aborted_renders_resume_into_the_one_shot_image() {
    // 96x54 in tiles of 16: 24 tiles. After 1, in the write of the 2nd of
    // the next run (1 whole), after 5 more, in the write of the 1st.
    interrupted_runs_match_one_shot(
        &[
            "render", "--scene", "cover", "--width", "96", "--spp", "4", "--tile", "16",
        ],
        "cover.png",
        &[
            ("after:1", 1),
            ("writing:2", 1),
            ("after:5", 5),
            ("writing:1", 0),
        ],
    );
}

#[test]
fn aborted_splatted_adaptive_and_partial_renders_resume_exactly() {
    // A splatted filter's window as a .film (tiles with margins), the
    // last tile aborted in its write.
    interrupted_runs_match_one_shot(
        &[
            "render",
            "--scene",
            "showcase",
            "--width",
            "64",
            "--spp",
            "4",
            "--tile",
            "8",
            "--filter",
            "mitchell",
            "--pixel-bounds",
            "5,50,3,30",
            "--samples",
            "1..4",
        ],
        "part.film",
        &[("after:3", 3), ("writing:4", 3)],
    );
    // Adaptive, to EXR.
    interrupted_runs_match_one_shot(
        &[
            "render",
            "--scene",
            "week09",
            "--width",
            "48",
            "--tile",
            "8",
            "--adaptive",
            "--min-spp",
            "8",
            "--max-spp",
            "32",
            "--sampler",
            "sobol",
        ],
        "adaptive.exr",
        &[("after:17", 17)],
    );
}

/// Starts a render whose appends after the first are held until a stop
/// (`hold:1`), waits until its checkpoint holds a tile, sends `signal`,
/// and returns its output: the render is still running then, however
/// fast the machine.
fn signalled(dir: &Path, render: &[&str], checkpoint: &Path, signal: &str) -> Output {
    let child = Command::new(env!("CARGO_BIN_EXE_strata"))
        .args(render)
        .current_dir(dir)
        .env(HOOK, "hold:1")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut child = child;
    let mut polls = 0;
    while !checkpoint.exists() || recorded(checkpoint) == 0 {
        polls += 1;
        if polls == 60_000 || child.try_wait().unwrap().is_some() {
            // Not left holding its tiles forever.
            child.kill().ok();
            panic!("no tile was checkpointed while the render ran");
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let kill = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    child.wait_with_output().unwrap()
}

#[test]
fn sigint_and_sigkill_leave_a_checkpoint_that_resumes_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let base = [
        "render", "--scene", "cover", "--width", "96", "--spp", "4", "--tile", "16",
    ];
    let mut one = base.to_vec();
    one.extend(["--no-checkpoint", "-o", "one.png"]);
    ok(d, &one);
    let want = bytes(&d.join("one.png"));
    std::fs::remove_file(d.join("one.png")).unwrap();
    for (signal, name) in [("-INT", "int.png"), ("-KILL", "kill.png")] {
        let checkpoint = d.join(format!("{name}.checkpoint"));
        let mut args = base.to_vec();
        args.extend(["-o", name]);
        let out = signalled(d, &args, &checkpoint, signal);
        let err = String::from_utf8_lossy(&out.stderr);
        match signal {
            "-INT" => {
                assert_eq!(out.status.code(), Some(130), "{err}");
                assert!(err.contains("interrupted: "), "{err}");
                assert!(err.contains("--resume"), "{err}");
            }
            _ => assert_eq!(out.status.signal(), Some(9)),
        }
        let left = names(d);
        assert_eq!(left, [format!("{name}.checkpoint")], "{signal}");
        let kept = recorded(&checkpoint);
        let out = ok(d, &["render", "--resume", &format!("{name}.checkpoint")]);
        let (k, t, r) = resumed_counts(&out);
        assert_eq!((k, k + r), (kept, t), "{signal}: {out}");
        assert!(k < t, "{signal}: the render was stopped before its end");
        assert!(
            bytes(&d.join(name)) == want,
            "{signal}: resumed file differs"
        );
        std::fs::remove_file(d.join(name)).unwrap();
    }
}

#[test]
fn checkpoints_are_refused_when_they_do_not_fit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = d.join("s.toml");
    let toml = SCENE;
    std::fs::write(&scene, toml).unwrap();
    let args = [
        "render",
        "--scene",
        "s.toml",
        "--width",
        "32",
        "--spp",
        "2",
        "--tile",
        "8",
        "-o",
        "s.png",
        "--threads",
        "1",
    ];
    let out = strata(d, &args, Some("after:2"));
    assert_eq!(out.status.signal(), Some(6));
    let before = names(d);
    let refused = |args: &[&str], want: &str| {
        let out = strata(d, args, None);
        let err = String::from_utf8_lossy(&out.stderr);
        // 1 for a refusal, 2 for clap's usage errors; not a signal.
        assert!(matches!(out.status.code(), Some(1 | 2)), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: `{want}` not in {err}");
        assert_eq!(names(d), before, "{args:?} changed the directory");
    };
    // A fresh render does not overwrite it.
    refused(&args, "--resume s.png.checkpoint");
    // --resume takes no other flag but --threads.
    // (Given at its default value, too: it is still a contradiction.)
    for flag in [
        &["--spp", "3"][..],
        &["--no-checkpoint"],
        &["-o", "t.png"],
        &["--seed", "0"],
        &["--scene", "week09"],
    ] {
        let mut a = vec!["render", "--resume", "s.png.checkpoint"];
        a.extend(flag);
        refused(&a, "give it alone (or with --threads)");
    }
    // Not a checkpoint.
    refused(&["render", "--resume", "s.toml"], "not a Strata checkpoint");
    // The checkpoint as an output.
    refused(
        &[
            "render",
            "--width",
            "8",
            "--checkpoint",
            "x.png",
            "-o",
            "x.png",
        ],
        "one of the render's outputs",
    );
    // The scene changed: named, and the checkpoint kept.
    std::fs::write(&scene, toml.replace("0.5, 0.5, 0.5", "0.5, 0.5, 0.6")).unwrap();
    refused(&["render", "--resume", "s.png.checkpoint"], "scene_hash is");
    std::fs::write(&scene, toml).unwrap();
    // Resumed from another directory (the paths were kept absolute), on
    // one thread.
    let elsewhere = tempfile::tempdir().unwrap();
    let path = d.join("s.png.checkpoint");
    let out = strata(
        elsewhere.path(),
        &[
            "render",
            "--resume",
            path.to_str().unwrap(),
            "--threads",
            "2",
        ],
        None,
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("on 2 threads"));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(names(d), ["s.png", "s.toml"]);
    assert!(names(elsewhere.path()).is_empty());
}

#[test]
fn a_render_without_output_resumes_to_the_same_default_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("scenes")).unwrap();
    let toml = SCENE;
    std::fs::write(d.join("scenes/s.toml"), toml).unwrap();
    let args = [
        "render",
        "--scene",
        "scenes/s.toml",
        "--width",
        "32",
        "--tile",
        "8",
    ];
    let out = strata(d, &args, Some("after:2"));
    assert_eq!(out.status.signal(), Some(6));
    // The scene file's stem names the output, as in a one-shot render.
    assert_eq!(names(d), ["s.png.checkpoint", "scenes"]);
    // A damaged record: it and the records after it are dropped, and
    // the resumed render says so.
    let path = d.join("s.png.checkpoint");
    let mut b = bytes(&path);
    let at = b.len() - 100;
    b[at] ^= 1;
    std::fs::write(&path, b).unwrap();
    let out = ok(d, &["render", "--resume", "s.png.checkpoint"]);
    assert!(out.contains("are dropped"), "{out}");
    assert_eq!(resumed_counts(&out).0, 1, "{out}");
    assert_eq!(names(d), ["s.png", "scenes"]);
    let one = ok(d, &{
        let mut a = args.to_vec();
        a.extend(["--no-checkpoint", "-o", "one.png"]);
        a
    });
    assert!(one.contains("one.png"));
    assert!(bytes(&d.join("s.png")) == bytes(&d.join("one.png")));
}

#[test]
fn a_resume_keeps_the_interrupted_runs_thread_count_unless_told() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = [
        "render",
        "--scene",
        "cover",
        "--width",
        "32",
        "--spp",
        "1",
        "--tile",
        "8",
        "--threads",
        "1",
        "-o",
        "c.png",
    ];
    assert_eq!(strata(d, &args, Some("after:1")).status.signal(), Some(6));
    let out = ok(d, &["render", "--resume", "c.png.checkpoint"]);
    assert!(out.contains("on 1 threads"), "{out}");
}
