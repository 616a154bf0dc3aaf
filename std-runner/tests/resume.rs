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
    // TILE, render id, index, count | paths, rays, shadow rays | pixels
    // | checksum.
    while at + 20 <= b.len() {
        let count = u32::from_le_bytes(b[at + 16..at + 20].try_into().unwrap()) as usize;
        let len = 52 + 64 * count;
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
    // --resume takes no flag that changes the image.
    // (Given at its default value, too: it is still a contradiction.)
    for flag in [
        &["--spp", "3"][..],
        &["--no-checkpoint"],
        &["--seed", "0"],
        &["--checkpoint", "c"],
    ] {
        let mut a = vec!["render", "--resume", "s.png.checkpoint"];
        a.extend(flag);
        refused(&a, "give it alone, or with what never changes the image");
    }
    // A scene may be named again (a moved file), but it must be the
    // checkpoint's.
    refused(
        &[
            "render",
            "--resume",
            "s.png.checkpoint",
            "--scene",
            "week09",
        ],
        "scene is `s` there, `week09` now",
    );
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
    // Resumed from another directory (paths are the checkpoint's
    // directory's), on two threads.
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

/// The integrator never changes the image, so a resume may change it: a
/// render interrupted with the scalar one and finished in lockstep is the
/// one-shot image, and the run facts name the integrator of the resume.
#[test]
fn a_resume_may_change_the_integrator() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = |integrator: &'static str, out: &'static str| {
        [
            "render",
            "--scene",
            "caustics",
            "--width",
            "48",
            "--spp",
            "2",
            "--tile",
            "8",
            "--threads",
            "1",
            "--integrator",
            integrator,
            "-o",
            out,
        ]
    };
    let mut one = args("lockstep", "one.png").to_vec();
    one.push("--no-checkpoint");
    ok(d, &one);
    let want = bytes(&d.join("one.png"));
    let cut = strata(d, &args("scalar", "c.png"), Some("after:1"));
    assert_eq!(cut.status.signal(), Some(6));
    let resume = [
        "render",
        "--resume",
        "c.png.checkpoint",
        "--integrator",
        "lockstep",
        "--stats",
        "s.json",
    ];
    let out = ok(d, &resume);
    let (kept, _, rendered) = resumed_counts(&out);
    assert!(kept >= 1 && rendered >= 1, "{out}");
    assert!(bytes(&d.join("c.png")) == want, "the resumed image differs");
    let facts: serde_json::Value = serde_json::from_slice(&bytes(&d.join("s.json"))).unwrap();
    assert_eq!(facts["integrator"], "lockstep");
}

/// Writes a checkpoint's header checksum again after an edit (as a tool
/// that meant the edit would), so what lies behind it is reached.
fn reseal_header(b: &mut Vec<u8>) {
    let end = b.windows(2).position(|w| w == b"\n\n").unwrap();
    let line = b[..end].iter().rposition(|&c| c == b'\n').unwrap() + 1;
    let h = strata_runner::hash::fnv1a(&b[..line]);
    let tail = b[end..].to_vec();
    b.truncate(line);
    b.extend_from_slice(format!("head_checksum={h:016x}").as_bytes());
    b.extend_from_slice(&tail);
}

/// The faults a damaged checkpoint once caused, each now refused with a
/// message and the directory left as it was: a window edited to be
/// empty (once an unbounded allocation), a tile of 0 (once a panic),
/// 65535 threads (once started), a flipped byte in the output's name
/// (once a file of another name) or in a built-in scene's hash (once
/// blamed on a changed scene file), the old format.
#[test]
fn damaged_checkpoints_are_refused_as_damage() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = [
        "render",
        "--scene",
        "cover",
        "--width",
        "96",
        "--spp",
        "1",
        "--tile",
        "16",
        "--pixel-bounds",
        "0,96,10,30",
        "-o",
        "out.png",
    ];
    assert_eq!(strata(d, &args, Some("after:2")).status.signal(), Some(6));
    let path = d.join("out.png.checkpoint");
    let good = bytes(&path);
    let text = String::from_utf8_lossy(&good).into_owned();
    let edit = |from: &str, to: &str, reseal: bool| -> String {
        let at = text
            .find(from)
            .unwrap_or_else(|| panic!("{from} in the header"));
        let mut b = good.clone();
        b.splice(at..at + from.len(), to.bytes());
        if reseal {
            // The records carry the old header's checksum: gone with it.
            let end = b.windows(2).position(|w| w == b"\n\n").unwrap() + 2;
            b.truncate(end);
            reseal_header(&mut b);
        }
        std::fs::write(&path, &b).unwrap();
        let out = strata(d, &["render", "--resume", "out.png.checkpoint"], None);
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert_eq!(out.status.code(), Some(1), "{from} -> {to}: {err}");
        assert_eq!(names(d), ["out.png.checkpoint"], "{from} -> {to}");
        err
    };
    for (from, to) in [
        ("0,96,10,30", "0,96,90,30"),
        ("\"tile\":16", "\"tile\":0"),
        ("\"threads\":2", "\"threads\":65535"),
        ("\"./out.png\"", "\"./nut.png\""),
        ("scene_hash=d", "scene_hash=e"),
    ] {
        let e = edit(from, to, false);
        assert!(e.contains("header is damaged"), "{from} -> {to}: {e}");
    }
    // Behind the checksum, the one check of every setting.
    for (from, to, want) in [
        (
            "[0,96,10,30]",
            "[0,96,90,30]",
            "--pixel-bounds 0,96,90,30 is empty",
        ),
        ("\"tile\":16", "\"tile\":0", "--tile 0 is not in 1..=4096"),
        (
            "\"threads\":2",
            "\"threads\":65535",
            "--threads 65535 is not in 1..=512",
        ),
        (
            "\"threads\":2",
            "\"threads\":600",
            "--threads 600 is not in 1..=512",
        ),
        (
            "scene_hash=d",
            "scene_hash=e",
            "this build's built-in scene differs",
        ),
    ] {
        let e = edit(from, to, true);
        assert!(e.contains(want), "{from} -> {to}: {e}");
    }
    // The format before header checksums.
    let mut old = good.clone();
    old[18] = b'1';
    std::fs::write(&path, &old).unwrap();
    let out = strata(d, &["render", "--resume", "out.png.checkpoint"], None);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("strata-checkpoint 1") && err.contains("strata-checkpoint 2"),
        "{err}"
    );
    // Untouched, it resumes.
    std::fs::write(&path, &good).unwrap();
    ok(d, &["render", "--resume", "out.png.checkpoint"]);
    assert_eq!(names(d), ["out.png"]);
}

/// A whole record whose pixels a film would refuse (a sample count of 0
/// or 2^32 - 1, resealed), or one spliced in from another seed's
/// checkpoint of the same frame: refused, not merged.
#[test]
fn checkpoint_records_are_checked_like_film_bodies() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let run = |seed: &str| {
        let args = [
            "render", "--scene", "cover", "--width", "32", "--spp", "2", "--tile", "8", "--seed",
            seed, "-o", "c.png",
        ];
        assert_eq!(strata(d, &args, Some("after:2")).status.signal(), Some(6));
        let b = bytes(&d.join("c.png.checkpoint"));
        std::fs::remove_file(d.join("c.png.checkpoint")).unwrap();
        b
    };
    let other = run("1");
    let good = run("0");
    let head = good.windows(2).position(|w| w == b"\n\n").unwrap() + 2;
    let fnv = strata_runner::hash::fnv1a;
    // The first record: 8 × 8 pixels.
    let len = 52 + 64 * 64;
    let resume = |b: &[u8]| {
        std::fs::write(d.join("c.png.checkpoint"), b).unwrap();
        let out = strata(d, &["render", "--resume", "c.png.checkpoint"], None);
        assert_eq!(names(d), ["c.png.checkpoint"]);
        assert_eq!(out.status.code(), Some(1));
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    for count in [0u32, u32::MAX] {
        let mut b = good.clone();
        // Pixel 5's sample count, then the record's checksum.
        let at = head + 44 + 5 * 64 + 32;
        b[at..at + 4].copy_from_slice(&count.to_le_bytes());
        let sum = fnv(&b[head..head + len - 8]);
        b[head + len - 8..head + len].copy_from_slice(&sum.to_le_bytes());
        let e = resume(&b);
        assert!(
            e.contains("is damaged") && e.contains(&format!("holds {count} samples")),
            "{e}"
        );
    }
    let mut b = good.clone();
    b.splice(head..head + len, other[head..head + len].iter().copied());
    let e = resume(&b);
    assert!(e.contains("belongs to another render"), "{e}");
    // Counts of what the tile traced that its samples cannot have (a
    // path count that would overflow the render's totals).
    for (at, value) in [(20, u64::MAX), (20, 1), (28, u64::MAX), (36, 1 << 40)] {
        let mut b = good.clone();
        b[head + at..head + at + 8].copy_from_slice(&value.to_le_bytes());
        let sum = fnv(&b[head..head + len - 8]);
        b[head + len - 8..head + len].copy_from_slice(&sum.to_le_bytes());
        let e = resume(&b);
        assert!(e.contains("is damaged") && e.contains("paths"), "{at}: {e}");
    }
}

/// A job directory moved elsewhere resumes where it now is (paths below
/// the checkpoint are kept relative to it), and `-o` writes the image
/// elsewhere: the output never changes the image.
#[test]
fn a_moved_job_resumes_and_takes_a_new_output() {
    let root = tempfile::tempdir().unwrap();
    let job = root.path().join("job");
    std::fs::create_dir(&job).unwrap();
    std::fs::write(job.join("s.toml"), SCENE).unwrap();
    let args = [
        "render", "--scene", "s.toml", "--width", "32", "--tile", "8", "-o", "out.png",
    ];
    assert_eq!(
        strata(&job, &args, Some("after:2")).status.signal(),
        Some(6)
    );
    let moved = root.path().join("moved");
    std::fs::rename(&job, &moved).unwrap();
    let out = ok(&moved, &["render", "--resume", "out.png.checkpoint"]);
    assert_eq!(resumed_counts(&out).0, 2, "{out}");
    assert_eq!(names(&moved), ["out.png", "s.toml"]);
    let mut one = args[..7].to_vec();
    one.extend(["--no-checkpoint", "-o", "one.png"]);
    ok(&moved, &one[..]);
    assert!(bytes(&moved.join("out.png")) == bytes(&moved.join("one.png")));
    // Again, resumed into another name and directory.
    std::fs::remove_file(moved.join("out.png")).unwrap();
    assert_eq!(
        strata(&moved, &args, Some("after:3")).status.signal(),
        Some(6)
    );
    std::fs::create_dir(moved.join("sub")).unwrap();
    ok(
        &moved,
        &[
            "render",
            "--resume",
            "out.png.checkpoint",
            "-o",
            "sub/new.png",
        ],
    );
    assert!(bytes(&moved.join("sub/new.png")) == bytes(&moved.join("one.png")));
    assert!(!moved.join("out.png.checkpoint").exists());
}

/// A checkpoint that cannot grow (here a file-size limit, as a full disk
/// would; the checkpoint is 64 bytes a pixel, the PNG far less) costs the
/// render nothing but the checkpoint: a warning, then the same image.
#[test]
fn a_checkpoint_that_cannot_be_written_costs_only_itself() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = [
        "render",
        "--scene",
        "cover",
        "--width",
        "200",
        "--spp",
        "2",
        "--threads",
        "1",
    ];
    let mut one = args.to_vec();
    one.extend(["--no-checkpoint", "-o", "one.png"]);
    ok(d, &one);
    let png = bytes(&d.join("one.png")).len() as u64;
    // Room for the PNG and one tile's record (32 × 32 × 64 bytes), not the
    // checkpoint of 200 × 112 pixels; blocks of 512 bytes. A process over
    // the limit is sent SIGXFSZ unless it ignores it, as one whose disk
    // is full is not.
    let blocks = (png.max(70_000) + 8 * 1024) / 512;
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "trap '' XFSZ; ulimit -f {blocks}; exec \"$0\" \"$@\""
        ))
        .arg(env!("CARGO_BIN_EXE_strata"))
        .args(args)
        .args(["-o", "out.png"])
        .current_dir(d)
        .env_remove(HOOK)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("warning: cannot append to the checkpoint `out.png.checkpoint`")
            && err.contains("rendering on without it"),
        "{err}"
    );
    assert_eq!(names(d), ["one.png", "out.png"]);
    assert!(bytes(&d.join("out.png")) == bytes(&d.join("one.png")));
}

/// A write killed in its moment leaves `.NAME.strata-tmp-PID` beside its
/// target; the next write of the same file removes those no process
/// holds, and leaves alone one a live writer holds (it locks its file
/// while it writes).
#[test]
fn temporary_files_of_killed_writes_are_removed() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let dead = ".out.film.strata-tmp-999999999";
    let dead_checkpoint = ".out.film.checkpoint.strata-tmp-999999998";
    let live = ".out.film.strata-tmp-4242";
    let other = ".other.film.strata-tmp-999999999";
    for f in [dead, dead_checkpoint, live, other] {
        std::fs::write(d.join(f), b"cut off").unwrap();
    }
    // A writer at work (on this host or another sharing the locks).
    let writer = std::fs::File::open(d.join(live)).unwrap();
    writer.lock().unwrap();
    ok(
        d,
        &[
            "render", "--scene", "cover", "--width", "16", "--spp", "1", "-o", "out.film",
        ],
    );
    let mut want = vec![live.to_string(), other.to_string(), "out.film".to_string()];
    want.sort();
    assert_eq!(names(d), want);
    drop(writer);
}

/// A second Ctrl-C quits at once and says the checkpoint keeps the
/// finished tiles (a tile held for good by the `stuck` hook keeps the
/// render running past the first signal, whatever the machine's speed).
#[test]
fn a_second_signal_quits_and_names_the_checkpoint() {
    use std::io::{BufRead, Read};
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut child = Command::new(env!("CARGO_BIN_EXE_strata"))
        .args([
            "render", "--scene", "cover", "--width", "64", "--spp", "1", "--tile", "16", "-o",
            "c.png",
        ])
        .current_dir(d)
        .env(HOOK, "stuck:1")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let checkpoint = d.join("c.png.checkpoint");
    let mut polls = 0;
    while !checkpoint.exists() || recorded(&checkpoint) == 0 {
        polls += 1;
        if polls == 60_000 || child.try_wait().unwrap().is_some() {
            // Not left stuck forever.
            child.kill().ok();
            panic!("no tile was checkpointed while the render ran");
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let signal = |child: &std::process::Child| {
        let kill = Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status()
            .unwrap();
        assert!(kill.success());
    };
    signal(&child);
    let mut err = std::io::BufReader::new(child.stderr.take().unwrap());
    let mut seen = String::new();
    // The first signal is taken: its line, then the second.
    while !seen.contains("stopping: finishing the tiles in flight") {
        let mut line = String::new();
        assert!(err.read_line(&mut line).unwrap() > 0, "{seen}");
        seen.push_str(&line);
    }
    signal(&child);
    err.read_to_string(&mut seen).unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "{seen}");
    assert!(
        seen.contains("quitting: the tiles finished so far are kept in `c.png.checkpoint`")
            && seen.contains("strata render --resume c.png.checkpoint"),
        "{seen}"
    );
    assert_eq!(names(d), ["c.png.checkpoint"]);
}

/// A checkpoint that holds every tile (a kill after the last one, before
/// the output was written) resumes to the output and says nothing was
/// left, not a speed of 0 samples/s.
#[test]
fn a_resume_with_nothing_left_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // 32 x 18 in tiles of 16: 4 tiles.
    let args = [
        "render", "--scene", "week09", "--width", "32", "--spp", "1", "--tile", "16", "-o", "w.png",
    ];
    assert_eq!(strata(d, &args, Some("after:4")).status.signal(), Some(6));
    assert_eq!(recorded(&d.join("w.png.checkpoint")), 4);
    let out = ok(d, &["render", "--resume", "w.png.checkpoint"]);
    assert!(
        out.contains("nothing was left to render: every tile came from the checkpoint"),
        "{out}"
    );
    assert!(!out.contains("samples/s"), "{out}");
    assert_eq!(names(d), ["w.png"]);
}

/// Resumed through a symbolic link, a checkpoint is the file it links to:
/// its paths are that file's directory's, and it is that file that is
/// finished and removed.
#[test]
fn a_checkpoint_resumed_through_a_link_is_the_file_it_links_to() {
    let root = tempfile::tempdir().unwrap();
    let job = root.path().join("job");
    std::fs::create_dir(&job).unwrap();
    let args = [
        "render", "--scene", "cover", "--width", "32", "--tile", "8", "-o", "out.png",
    ];
    assert_eq!(
        strata(&job, &args, Some("after:2")).status.signal(),
        Some(6)
    );
    std::os::unix::fs::symlink(job.join("out.png.checkpoint"), root.path().join("c.ckpt")).unwrap();
    ok(root.path(), &["render", "--resume", "c.ckpt"]);
    assert_eq!(names(&job), ["out.png"]);
    let mut top = names(root.path());
    top.retain(|n| n != "job");
    // The link is left, dangling: it was never the checkpoint.
    assert_eq!(top, ["c.ckpt"]);
}

/// What is not a checkpoint is refused from its first bytes: a device
/// that never ends, or a file of gigabytes, costs no memory.
#[test]
fn a_huge_or_endless_file_is_refused_from_its_first_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let big = d.join("big.checkpoint");
    std::fs::File::create(&big)
        .unwrap()
        .set_len(3 << 30)
        .unwrap();
    for target in [big.to_str().unwrap(), "/dev/zero"] {
        // Half a gigabyte of address space: far less than the file.
        let out = Command::new("sh")
            .arg("-c")
            .arg("ulimit -v 524288; exec \"$0\" \"$@\"")
            .arg(env!("CARGO_BIN_EXE_strata"))
            .args(["render", "--resume", target])
            .current_dir(d)
            .env_remove(HOOK)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{target}: {err}");
        assert!(err.contains("not a Strata checkpoint"), "{target}: {err}");
    }
    // A checkpoint whose last record claims 2^32 - 1 pixels: its tiles
    // resume, and the claim is dropped unread.
    let args = [
        "render", "--scene", "week09", "--width", "32", "--tile", "8", "-o", "w.png",
    ];
    assert_eq!(strata(d, &args, Some("after:1")).status.signal(), Some(6));
    let path = d.join("w.png.checkpoint");
    let mut b = bytes(&path);
    let head = b.windows(2).position(|w| w == b"\n\n").unwrap() + 2;
    let mut claim = b[head..head + 44].to_vec();
    claim[16..20].copy_from_slice(&u32::MAX.to_le_bytes());
    b.extend_from_slice(&claim);
    std::fs::write(&path, &b).unwrap();
    let out = Command::new("sh")
        .arg("-c")
        .arg("ulimit -v 1048576; exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_strata"))
        .args(["render", "--resume", "w.png.checkpoint"])
        .current_dir(d)
        .env_remove(HOOK)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        text.contains("it holds 1 tile whole; 44 bytes of tile records"),
        "{text}"
    );
}

/// `-o` may rename the output, not change its kind: an image of a window
/// of a splatted render renders the window's border too, a film does not.
#[test]
fn a_resume_keeps_its_outputs_kind() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = [
        "render",
        "--scene",
        "cover",
        "--width",
        "32",
        "--tile",
        "8",
        "--filter",
        "mitchell",
        "--pixel-bounds",
        "4,28,2,16",
        "-o",
        "c.png",
    ];
    assert_eq!(strata(d, &args, Some("after:1")).status.signal(), Some(6));
    let out = strata(
        d,
        &["render", "--resume", "c.png.checkpoint", "-o", "c.film"],
        None,
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("writes an image (.png or .exr)"), "{err}");
    // Renamed within its kind, into a directory that does not exist: the
    // usual message, not "moved?".
    let out = strata(
        d,
        &["render", "--resume", "c.png.checkpoint", "-o", "no/c.exr"],
        None,
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("its directory `no` does not exist"), "{err}");
    ok(
        d,
        &["render", "--resume", "c.png.checkpoint", "-o", "c.exr"],
    );
    assert_eq!(names(d), ["c.exr"]);
}

/// A scene file or an output that is a link inside the job directory is
/// kept as the link's name, as a one-shot render reads and writes it.
#[test]
fn links_in_a_job_directory_are_kept_as_links() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir(d.join("scenes")).unwrap();
    std::fs::write(d.join("scenes/real.toml"), SCENE).unwrap();
    std::os::unix::fs::symlink("scenes/real.toml", d.join("s.toml")).unwrap();
    let args = [
        "render", "--scene", "s.toml", "--width", "32", "--tile", "8", "-o", "out.png",
    ];
    assert_eq!(strata(d, &args, Some("after:2")).status.signal(), Some(6));
    let text = String::from_utf8_lossy(&bytes(&d.join("out.png.checkpoint"))).into_owned();
    assert!(text.contains("\"scene\":\"./s.toml\""), "{text:.400}");
    let out = ok(d, &["render", "--resume", "out.png.checkpoint"]);
    assert_eq!(resumed_counts(&out).0, 2, "{out}");
    assert_eq!(names(d), ["out.png", "s.toml", "scenes"]);
}

/// A second process cannot resume a checkpoint a render is appending to
/// (a requeued job whose first run still lives): it is locked from the
/// moment it is opened, before anything is read.
#[test]
fn a_checkpoint_in_use_is_refused_before_it_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut child = Command::new(env!("CARGO_BIN_EXE_strata"))
        .args([
            "render", "--scene", "cover", "--width", "64", "--spp", "1", "--tile", "16", "-o",
            "c.png",
        ])
        .current_dir(d)
        .env(HOOK, "stuck:1")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let checkpoint = d.join("c.png.checkpoint");
    let mut polls = 0;
    while !checkpoint.exists() || recorded(&checkpoint) == 0 {
        polls += 1;
        if polls == 60_000 || child.try_wait().unwrap().is_some() {
            child.kill().ok();
            panic!("no tile was checkpointed while the render ran");
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let out = strata(d, &["render", "--resume", "c.png.checkpoint"], None);
    child.kill().ok();
    child.wait().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("in use by another strata process"), "{err}");
}

/// A FIFO (or anything but a regular file) named like a temporary file
/// is left alone, not opened: opening it would wait forever.
#[test]
fn a_fifo_named_like_a_temporary_file_is_left_alone() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let made = Command::new("mkfifo")
        .arg(d.join(".out.png.strata-tmp-1"))
        .status()
        .unwrap();
    assert!(made.success());
    ok(
        d,
        &[
            "render",
            "--scene",
            "cover",
            "--width",
            "16",
            "--spp",
            "1",
            "--no-checkpoint",
            "-o",
            "out.png",
        ],
    );
    assert_eq!(names(d), [".out.png.strata-tmp-1", "out.png"]);
}
