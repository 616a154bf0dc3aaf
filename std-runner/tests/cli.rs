//! The `strata` command run as a process: bit-identical images across
//! thread counts, tile sizes and runs; seeds matter; TOML scenes with
//! every material and an image texture; and every kind of bad input
//! refused with a clear message, a non-zero exit and no file left behind.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn strata(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_strata"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the strata binary runs")
}

fn ok(dir: &Path, args: &[&str]) -> String {
    let out = strata(dir, args);
    assert!(
        out.status.success(),
        "strata {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Runs a command that must fail; returns its stderr. Checks the exit
/// code and that the directory holds exactly the files it held before.
fn refused(dir: &Path, args: &[&str]) -> String {
    let before = listing(dir);
    let out = strata(dir, args);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        !out.status.success(),
        "strata {args:?} succeeded but should not"
    );
    assert_ne!(out.status.code(), Some(0));
    assert_eq!(listing(dir), before, "strata {args:?} left files behind");
    assert!(!err.trim().is_empty(), "no message for {args:?}");
    assert!(!err.contains("panicked"), "a panic for {args:?}: {err}");
    err
}

fn listing(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    v.sort();
    v
}

fn bytes(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn no_arguments_render_week09() {
    let dir = tempfile::tempdir().unwrap();
    let out = ok(dir.path(), &[]);
    assert!(out.contains("week09: 320x180 30 spp"), "{out}");
    let png = bytes(&dir.path().join("week09.png"));
    assert_eq!(&png[1..4], b"PNG");
    assert_eq!(listing(dir.path()).len(), 1, "only the image is written");
}

#[test]
fn threads_tiles_and_runs_give_identical_files() {
    let dir = tempfile::tempdir().unwrap();
    let base = [
        "render",
        "--scene",
        "showcase",
        "--width",
        "96",
        "--spp",
        "4",
        "--sampler",
        "stratified",
    ];
    let run = |name: &str, extra: &[&str]| {
        let mut args: Vec<&str> = base.to_vec();
        args.extend_from_slice(extra);
        args.extend_from_slice(&["-o", name]);
        ok(dir.path(), &args);
        bytes(&dir.path().join(name))
    };
    let one = run("t1.png", &["--threads", "1"]);
    assert_eq!(run("t2.png", &["--threads", "2"]), one, "1 vs 2 threads");
    assert_eq!(
        run("tile7.png", &["--threads", "2", "--tile", "7"]),
        one,
        "tile 7"
    );
    assert_eq!(
        run("tile64.png", &["--threads", "3", "--tile", "64"]),
        one,
        "tile 64"
    );
    assert_eq!(run("again.png", &["--threads", "1"]), one, "a second run");
    assert_ne!(run("seed.png", &["--seed", "1"]), one, "another seed");
    // Sobol' too is independent of threads and tiles.
    let sobol = |name: &str, extra: &[&str]| {
        let mut args = vec![
            "render", "--scene", "showcase", "--width", "96", "--spp", "4",
        ];
        args.extend_from_slice(&["--sampler", "sobol", "-o", name]);
        args.extend_from_slice(extra);
        ok(dir.path(), &args);
        bytes(&dir.path().join(name))
    };
    let s1 = sobol("s1.png", &["--threads", "1"]);
    assert_eq!(sobol("s2.png", &["--threads", "2", "--tile", "9"]), s1);
    assert_ne!(s1, one);
    // EXR too.
    let a = run("a.exr", &["--threads", "1"]);
    assert_eq!(run("b.exr", &["--threads", "2", "--tile", "5"]), a);
    assert_eq!(&a[..4], &[0x76, 0x2f, 0x31, 0x01], "EXR magic");
}

#[test]
fn png_metadata_defines_the_render() {
    let dir = tempfile::tempdir().unwrap();
    ok(
        dir.path(),
        &[
            "render", "--width", "32", "--spp", "2", "--seed", "9", "-o", "m.png",
        ],
    );
    let text = String::from_utf8_lossy(&bytes(&dir.path().join("m.png"))).into_owned();
    for want in [
        "strata.seed",
        "9",
        "strata.spp",
        "strata.sampler",
        "independent",
        "strata.scene_hash",
    ] {
        assert!(text.contains(want), "missing {want}");
    }
    // Nothing that varies between runs.
    assert!(!text.contains("strata.threads") && !text.contains("wall"));
}

#[test]
fn gamma_2_is_the_course_curve() {
    let dir = tempfile::tempdir().unwrap();
    ok(
        dir.path(),
        &["render", "--width", "32", "--spp", "2", "-o", "s.png"],
    );
    ok(
        dir.path(),
        &[
            "render", "--width", "32", "--spp", "2", "--gamma", "2", "-o", "g.png",
        ],
    );
    assert_ne!(
        bytes(&dir.path().join("s.png")),
        bytes(&dir.path().join("g.png"))
    );
}

const SCENE: &str = r#"
background = [0.1, 0.1, 0.12]

[camera]
look_from = [0.0, 1.0, 3.0]
look_at = [0.0, 0.0, 0.0]
vfov = 50.0

[render]
width = 48
spp = 4
max_depth = 6

[textures.checker]
kind = "checker"
scale = 0.5
even = [0.2, 0.2, 0.2]
odd = [0.9, 0.9, 0.9]

[textures.picture]
kind = "image"
path = "picture.png"

[materials.ground]
kind = "lambertian"
texture = "checker"

[materials.globe]
kind = "lambertian"
texture = "picture"

[materials.blinn]
kind = "blinn"
albedo = [0.4, 0.5, 0.4]
kd = 0.5
ks = 0.6
exponent = 8.0

[materials.phong]
kind = "phong"
albedo = [0.8, 0.5, 0.4]
kd = 0.5
ks = 0.2
exponent = 30.0

[materials.nblinn]
kind = "blinn_normalized"
albedo = [0.8, 0.5, 0.8]
kd = 0.5
ks = 0.5
exponent = 40.0

[materials.nphong]
kind = "phong_normalized"
texture = "checker"
kd = 0.5
ks = 0.3
exponent = 10.0

[materials.ct]
kind = "cook_torrance"
albedo = [0.7, 0.2, 0.2]
kd = 0.6
ks = 0.4
alpha = 0.3
ior = 1.5

[materials.mirror]
kind = "mirror"
albedo = [0.9, 0.9, 0.9]

[materials.metal]
kind = "metal"
albedo = [0.8, 0.6, 0.2]
roughness = 0.3

[materials.glass]
kind = "dielectric"
ior = 1.5

[materials.lamp]
kind = "light"
emit = [10.0, 10.0, 10.0]

[[spheres]]
center = [0.0, -100.5, 0.0]
radius = 100.0
material = "ground"

[[spheres]]
center = [-1.0, 0.0, 0.0]
radius = 0.5
material = "globe"

[[spheres]]
center = [0.0, 0.0, 0.0]
radius = 0.5
material = "blinn"

[[spheres]]
center = [1.0, 0.0, 0.0]
radius = 0.5
material = "glass"

[[spheres]]
center = [-0.5, 0.0, -1.0]
radius = 0.4
material = "metal"

[[spheres]]
center = [0.5, 0.0, -1.0]
radius = 0.4
material = "mirror"

[[spheres]]
center = [1.5, 0.0, -1.0]
radius = 0.4
material = "ct"

[[spheres]]
center = [-1.5, 0.0, -1.0]
radius = 0.4
material = "phong"

[[spheres]]
center = [0.0, 0.0, -2.0]
radius = 0.4
material = "nblinn"

[[spheres]]
center = [1.0, 0.0, -2.0]
radius = 0.4
material = "nphong"

[[spheres]]
center = [0.0, 2.0, 0.0]
radius = 0.3
material = "lamp"
"#;

/// Writes the scene file and its 4 × 2 image texture.
fn scene_dir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.toml"), SCENE).unwrap();
    let file = std::fs::File::create(dir.path().join("picture.png")).unwrap();
    let mut enc = png::Encoder::new(file, 4, 2);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header().unwrap();
    w.write_image_data(
        &[255u8, 0, 0]
            .repeat(4)
            .into_iter()
            .chain([0u8, 0, 255].repeat(4))
            .collect::<Vec<u8>>(),
    )
    .unwrap();
    w.finish().unwrap();
    dir
}

#[test]
fn toml_scene_with_every_material_renders() {
    let dir = scene_dir();
    let out = ok(
        dir.path(),
        &["render", "--scene", "scene.toml", "-o", "s.png"],
    );
    assert!(out.contains("scene: 48x27 4 spp"), "{out}");
    let a = bytes(&dir.path().join("s.png"));
    ok(
        dir.path(),
        &[
            "render",
            "--scene",
            "scene.toml",
            "--threads",
            "1",
            "--tile",
            "3",
            "-o",
            "t.png",
        ],
    );
    assert_eq!(bytes(&dir.path().join("t.png")), a);
}

/// Replaces the first occurrence of `from` in the scene text.
fn broken(dir: &Path, from: &str, to: &str) -> String {
    assert!(SCENE.contains(from), "{from}");
    std::fs::write(dir.join("bad.toml"), SCENE.replacen(from, to, 1)).unwrap();
    refused(dir, &["render", "--scene", "bad.toml", "-o", "bad.png"])
}

fn line_of(needle: &str) -> usize {
    SCENE[..SCENE.find(needle).unwrap()].matches('\n').count() + 1
}

#[test]
fn bad_scene_files_name_file_line_and_field() {
    let dir = scene_dir();
    let d = dir.path();
    let e = broken(
        d,
        "radius = 0.5\nmaterial = \"blinn\"",
        "radius = -0.5\nmaterial = \"blinn\"",
    );
    assert!(
        e.contains("bad.toml:") && e.contains("spheres[2].radius") && e.contains("positive"),
        "{e}"
    );
    assert!(
        e.contains(&format!(
            ":{}:",
            line_of("radius = 0.5\nmaterial = \"blinn\"")
        )),
        "{e}"
    );
    let e = broken(d, "material = \"blinn\"", "material = \"velvet\"");
    assert!(
        e.contains("spheres[2].material") && e.contains("unknown material `velvet`"),
        "{e}"
    );
    let e = broken(d, "kind = \"mirror\"", "kind = \"velvet\"");
    assert!(
        e.contains("bad.toml:") && e.contains("materials.mirror") && e.contains("velvet"),
        "{e}"
    );
    let e = broken(d, "vfov = 50.0", "vfov = nan");
    assert!(
        e.contains("camera.vfov") && e.contains(&format!(":{}:", line_of("vfov"))),
        "{e}"
    );
    let e = broken(d, "center = [0.0, 0.0, 0.0]", "center = [0.0, nan, 0.0]");
    assert!(
        e.contains("spheres[2].center") && e.contains("finite"),
        "{e}"
    );
    let e = broken(
        d,
        "radius = 0.4\nmaterial = \"metal\"",
        "material = \"metal\"",
    );
    assert!(
        e.contains("bad.toml:") && e.contains("spheres[4]") && e.contains("radius"),
        "missing field: {e}"
    );
    let e = broken(d, "ks = 0.5\nexponent = 40.0", "ks = 0.6\nexponent = 40.0");
    assert!(
        e.contains("materials.nblinn") && e.contains("kd + ks"),
        "{e}"
    );
    let e = broken(d, "path = \"picture.png\"", "path = \"missing.png\"");
    assert!(
        e.contains("textures.picture.path") && e.contains("missing.png"),
        "{e}"
    );
    let e = broken(d, "emit = [10.0, 10.0, 10.0]", "emit = [10.0, -1.0, 10.0]");
    assert!(e.contains("materials.lamp.emit"), "{e}");
    let e = broken(d, "width = 48", "width = 0");
    assert!(e.contains("render.width"), "{e}");
    // Accepted once but never honoured: a sphere too big for f32's
    // squares, one too small to resolve at the scene's scale, and
    // radiances past the film's clamp.
    let e = broken(
        d,
        "radius = 0.3\nmaterial = \"lamp\"",
        "radius = 1e20\nmaterial = \"lamp\"",
    );
    assert!(e.contains("radius") && e.contains("never be drawn"), "{e}");
    let e = broken(d, "center = [0.0, 2.0, 0.0]", "center = [0.0, 2.0, 2e18]");
    assert!(e.contains(".center") && e.contains("never be drawn"), "{e}");
    let e = broken(
        d,
        "center = [1.0, 0.0, -2.0]\nradius = 0.4",
        "center = [1.0, 0.0, -1e6]\nradius = 1e-4",
    );
    assert!(
        e.contains(&format!(
            ":{}:",
            line_of("radius = 0.4\nmaterial = \"nphong\"")
        )) && e.contains("spheres[9].radius")
            && e.contains("below what f32 resolves"),
        "{e}"
    );
    // A light past the cap renders (its light on surfaces is right) but
    // says that where it is seen directly its pixels clamp.
    std::fs::write(
        d.join("bright.toml"),
        SCENE.replacen("emit = [10.0, 10.0, 10.0]", "emit = [10.0, 1e5, 10.0]", 1),
    )
    .unwrap();
    let out = strata(
        d,
        &[
            "render",
            "--scene",
            "bright.toml",
            "--width",
            "8",
            "-o",
            "bright.png",
        ],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("warning: a light emits 1e5") && err.contains("clamped"),
        "{err}"
    );
    std::fs::remove_file(d.join("bright.png")).unwrap();
    let e = broken(d, "emit = [10.0, 10.0, 10.0]", "emit = [10.0, 1e39, 10.0]");
    assert!(e.contains("materials.lamp.emit"), "{e}");
    let e = broken(
        d,
        "background = [0.1, 0.1, 0.12]",
        "background = [0.1, 7e4, 0.12]",
    );
    assert!(e.contains("background") && e.contains("65536"), "{e}");
    // A fourth component was once dropped without a word.
    let e = broken(
        d,
        "center = [0.0, 2.0, 0.0]",
        "center = [0.0, 2.0, 0.0, 1.0]",
    );
    assert!(
        e.contains(&format!(":{}:", line_of("center = [0.0, 2.0, 0.0]")))
            && e.contains("spheres[10].center")
            && e.contains("4 numbers where a point or direction takes three"),
        "{e}"
    );
    for key in ["look_from", "look_at"] {
        let at = SCENE.find(&format!("{key} = [")).unwrap();
        let close = at + SCENE[at..].find(']').unwrap();
        let line = &SCENE[at..=close];
        let e = broken(d, line, &line.replace(']', ", 0.0]"));
        assert!(
            e.contains(&format!(":{}:", line_of(line)))
                && e.contains(&format!("camera.{key}"))
                && e.contains("4 numbers"),
            "{e}"
        );
    }
    let e = broken(d, "[camera]", "[camera]\nzoom = 2.0");
    assert!(
        e.contains("camera") && e.contains("zoom"),
        "unknown field: {e}"
    );
}

/// Each message names the key at fault, on its line, in one line.
#[test]
fn scene_file_messages_blame_the_right_key() {
    let dir = scene_dir();
    let d = dir.path();
    let one_line = |e: &str| assert_eq!(e.trim_end().lines().count(), 1, "{e}");
    // A camera that is valid key by key but not representable: the key
    // that makes it so, not "look_from and look_at coincide".
    let e = broken(d, "vfov = 50.0", "vfov = 1e-40");
    assert!(e.contains("camera.vfov") && e.contains("too narrow"), "{e}");
    let e = broken(
        d,
        "look_from = [0.0, 1.0, 3.0]",
        "look_from = [0.0, 1.0, 1e30]",
    );
    assert!(
        e.contains(&format!(":{}: camera.look_from:", line_of("look_from")))
            && e.contains("too far"),
        "{e}"
    );
    let e = broken(d, "look_at = [0.0, 0.0, 0.0]", "look_at = [0.0, 1.0, 3.0]");
    assert!(e.contains("coincide"), "{e}");
    // A missing top-level table is the file's, not its first table's.
    let no_materials: String = SCENE.split("\n[materials.").next().unwrap().to_string()
        + "\n[[spheres]]\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = \"x\"\n";
    std::fs::write(d.join("bad.toml"), no_materials).unwrap();
    let e = refused(d, &["render", "--scene", "bad.toml", "-o", "bad.png"]);
    assert!(
        e.contains(":1: (top level): missing field `materials`"),
        "{e}"
    );
    // A type error names the key.
    let e = broken(d, "vfov = 50.0", "vfov = \"wide\"");
    assert!(
        e.contains(&format!(":{}: camera.vfov: invalid type", line_of("vfov"))),
        "{e}"
    );
    // A material's bad key is placed on its own line.
    let e = broken(d, "roughness = 0.3", "roughness = 3.0");
    assert!(
        e.contains(&format!(
            ":{}: materials.metal.roughness",
            line_of("roughness = 0.3")
        )),
        "{e}"
    );
    // So are a material's values of the wrong type or length and its
    // unknown keys (serde reports them against the table).
    for (to, key) in [
        ("roughness = \"x\"", "roughness"),
        ("roughness = [0.3]", "roughness"),
    ] {
        let e = broken(d, "roughness = 0.3", to);
        assert!(
            e.contains(&format!(
                ":{}: materials.metal.{key}:",
                line_of("roughness = 0.3")
            )),
            "{e}"
        );
    }
    let e = broken(d, "roughness = 0.3", "roughness = 0.3\nfuzz = 1.0");
    assert!(
        e.contains(&format!(
            ":{}: materials.metal.fuzz: unknown field",
            line_of("roughness = 0.3") + 1
        )),
        "{e}"
    );
    // A string over two lines stays a one-line message.
    let e = broken(d, "kind = \"mirror\"", "kind = \"\"\"mir\nror\"\"\"");
    assert!(e.contains("mir\\nror"), "{e}");
    one_line(&e);
    // Not UTF-8: the line of the first bad byte.
    let mut bytes = SCENE.as_bytes().to_vec();
    let at = SCENE.find("vfov").unwrap();
    bytes.splice(at..at, [b'#', 0xff, b'\n']);
    std::fs::write(d.join("bad.toml"), bytes).unwrap();
    let e = refused(d, &["render", "--scene", "bad.toml", "-o", "bad.png"]);
    assert!(
        e.contains(&format!("bad.toml:{}: (file): not UTF-8", line_of("vfov"))),
        "{e}"
    );
    one_line(&e);
    // The file's aspect is the file's, not a --aspect never given.
    let e = broken(d, "width = 48", "width = 48\naspect = 1e-6");
    assert!(
        e.contains("the scene's aspect") && !e.contains("--aspect 0"),
        "{e}"
    );
    // A missing output directory says so.
    let e = refused(d, &["render", "--width", "8", "-o", "no/such/dir/x.png"]);
    assert!(e.contains("directory `no/such/dir` does not exist"), "{e}");
}

/// `strata --help` says what `render` writes and that it resumes.
#[test]
fn help_names_every_output_of_render() {
    let out = ok(Path::new("."), &["--help"]);
    let line = out
        .lines()
        .find(|l| l.trim_start().starts_with("render"))
        .unwrap_or_else(|| panic!("{out}"));
    assert!(
        line.contains("PNG")
            && line.contains("EXR")
            && line.contains(".film")
            && line.contains("--resume"),
        "{line}"
    );
}

/// Help texts say only what a user can act on: every built-in scene, no
/// source-code links, no files outside the repository.
#[test]
fn help_texts_are_self_contained() {
    let dir = tempfile::tempdir().unwrap();
    for cmd in ["render", "converge", "adaptive", "filters", "aliasing"] {
        let help = ok(dir.path(), &[cmd, "--help"]);
        assert!(help.contains("--scene"), "{cmd}");
        assert!(
            help.contains("horizon") && help.contains("caustics"),
            "{cmd}"
        );
        for bad in ["[`", "COURSE.md", "DESIGN.md"] {
            assert!(!help.contains(bad), "{cmd} --help holds `{bad}`");
        }
    }
}

#[test]
fn bad_flags_are_refused_before_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Sparse: no disk, and never read.
    std::fs::File::create(d.join("huge.toml"))
        .unwrap()
        .set_len(300 << 20)
        .unwrap();
    for (args, want) in [
        (vec!["render", "--width", "0"], "--width"),
        (vec!["render", "--spp", "0"], "--spp"),
        (vec!["render", "--spp", "99999999"], "--spp"),
        (vec!["render", "--max-depth", "0"], "--max-depth"),
        (vec!["render", "--threads", "0"], "--threads"),
        (vec!["render", "--aspect", "-2"], "--aspect"),
        (vec!["render", "--aspect", "nan"], "--aspect"),
        (vec!["render", "--height", "9", "--aspect", "2"], "--aspect"),
        (vec!["render", "--sampler", "bogus"], "--sampler"),
        (
            vec!["render", "--scene", "nonesuch"],
            "unknown scene `nonesuch`",
        ),
        (
            vec!["render", "--scene", "missing.toml"],
            "missing.toml: cannot read the scene file",
        ),
        (
            vec!["render", "--scene", "/dev/zero"],
            "/dev/zero: not a regular file",
        ),
        (
            vec!["render", "--scene", "huge.toml"],
            "huge.toml: larger than 256 MiB",
        ),
        (vec!["render", "-o", "image.jpg"], ".png or .exr"),
        (
            vec!["render", "-o", "no/such/dir/x.png"],
            "cannot write output",
        ),
        (
            vec!["render", "--width", "16384", "--aspect", "0.01"],
            "height",
        ),
    ] {
        let e = refused(d, &args);
        assert!(e.contains(want), "{args:?}: {e}");
    }
    // A directory as output.
    std::fs::create_dir(d.join("out.png")).unwrap();
    let e = refused(d, &["render", "-o", "out.png"]);
    assert!(e.contains("directory"), "{e}");
}

/// The one run of the benchmark suite in the tests (it takes half a
/// minute even at one repetition): the table, the JSON report with every
/// comparison, ratio and goal, and the refusals that leave a report alone.
#[test]
fn bench_writes_a_table_and_json() {
    let dir = tempfile::tempdir().unwrap();
    let out = ok(
        dir.path(),
        &[
            "bench",
            "--repetitions",
            "1",
            "--min-time-ms",
            "1",
            "--json",
            "b.json",
        ],
    );
    assert!(
        out.contains("closest/cover_camera packet / scalar"),
        "{out}"
    );
    assert!(out.contains("render/week09 2 threads / 1 thread"), "{out}");
    assert!(
        out.contains("ratios")
            && out.contains("goals")
            && (out.contains("PASS") || out.contains("FAIL") || out.contains("not judged")),
        "{out}"
    );
    let text = String::from_utf8(bytes(&dir.path().join("b.json"))).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    for key in ["simd", "cpu", "figures", "ratios", "goals"] {
        assert!(json.get(key).is_some(), "{key} missing");
    }
    assert_eq!(
        json["integrator"],
        strata::render::Integrator::default().name()
    );
    let figures = json["figures"].as_array().unwrap();
    let comparisons: std::collections::BTreeSet<String> = figures
        .iter()
        .map(|f| format!("{}/{}", f["group"], f["comparison"]))
        .collect();
    assert_eq!(comparisons.len() as u64, strata_runner::bench::COMPARISONS);
    assert!(figures.iter().all(|f| {
        let m = f["mega_per_s"]["median"].as_f64().unwrap();
        m > 0.0 && m.is_finite()
    }));
    let names = |key: &str| -> Vec<String> {
        json[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|g| g["name"].as_str().unwrap().to_string())
            .collect()
    };
    assert!(names("ratios").contains(&"render/cover 2 threads / 1 thread".to_string()));
    let packet = "closest/cover_camera packet / scalar";
    if strata_runner::bench::target(packet, strata::trace::simd_level()).is_some() {
        assert!(names("goals").contains(&packet.to_string()));
    }
    assert!(names("goals").contains(&"render/week09 2 threads / 1 thread".to_string()));
    // A refused run leaves an existing report alone.
    let before = bytes(&dir.path().join("b.json"));
    let e = refused(
        dir.path(),
        &["bench", "--json", "b.json", "--repetitions", "0"],
    );
    assert!(e.contains("--repetitions"), "{e}");
    assert_eq!(bytes(&dir.path().join("b.json")), before);
    let e = refused(dir.path(), &["bench", "--json", "b.txt"]);
    assert!(e.contains(".json"), "{e}");
    let e = refused(dir.path(), &["bench", "--json", "no/such/dir/b.json"]);
    assert!(e.contains("cannot write"), "{e}");
}

/// A full or closed stdout (`strata ... > /dev/full`, `| head`) is no
/// reason to fail: the image is written, and the report is lost quietly.
#[test]
fn a_full_stdout_is_not_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_strata"))
        .args(["render", "--width", "16", "--spp", "1", "-o", "f.png"])
        .current_dir(dir.path())
        .stdout(full)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.path().join("f.png").exists());
}

fn png_size(p: &Path) -> (u32, u32) {
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes(p)));
    let reader = decoder.read_info().unwrap();
    let info = reader.info();
    (info.width, info.height)
}

/// The 8-bit RGB samples of a PNG, row-major.
fn png_rgb8(p: &Path) -> Vec<u8> {
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes(p)));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(
        (info.color_type, info.bit_depth),
        (png::ColorType::Rgb, png::BitDepth::Eight)
    );
    buf.truncate(info.buffer_size());
    buf
}

#[test]
fn converge_writes_csv_and_plot_and_caches_its_reference() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = [
        "converge",
        "--width",
        "48",
        "--pixel-bounds",
        "8,40,4,24",
        "--samplers",
        "independent,sobol",
        "--reference-spp",
        "4096",
        "--cache-dir",
        "cache",
        "--csv",
        "c.csv",
        "--plot",
        "c.png",
    ];
    let first = ok(d, &args);
    assert!(first.contains("32x20 crop at (8, 4) of 48x27"), "{first}");
    assert!(first.contains("rendered in"), "{first}");
    let csv = std::fs::read_to_string(d.join("c.csv")).unwrap();
    let rows: Vec<(String, u32, f64)> = csv
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[0].into(), f[1].parse().unwrap(), f[2].parse().unwrap())
        })
        .collect();
    assert_eq!(csv.lines().next(), Some("sampler,spp,rmse"));
    assert_eq!(rows.len(), 10, "{csv}");
    let at = |s: &str, spp: u32| {
        rows.iter()
            .find(|r| r.0 == s && r.1 == spp)
            .unwrap_or_else(|| panic!("no {s} {spp} in {csv}"))
            .2
    };
    // The study measures what it should: error falls with spp, and faster
    // for Sobol' than for independent samples.
    for s in ["independent", "sobol"] {
        assert!(at(s, 256) < 0.25 * at(s, 4), "{csv}");
    }
    assert!(at("sobol", 256) < at("independent", 256), "{csv}");
    assert_eq!(png_size(&d.join("c.png")), (800, 560));
    assert_eq!(std::fs::read_dir(d.join("cache")).unwrap().count(), 1);

    // Again: the reference comes from the cache, and the numbers repeat.
    let second = ok(d, &args);
    assert!(
        second.contains("reference: sobol 4096 spp, cached"),
        "{second}"
    );
    assert_eq!(std::fs::read_to_string(d.join("c.csv")).unwrap(), csv);
    // A slope per sampler.
    assert!(
        second
            .lines()
            .any(|l| l.starts_with("sobol") && l.contains("-0.")),
        "{second}"
    );
}

#[test]
fn aliasing_demo_puts_labelled_panels_side_by_side() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = ok(
        d,
        &[
            "aliasing",
            "--width",
            "64",
            "--reference-spp",
            "64",
            "-o",
            "a.png",
        ],
    );
    for s in [
        "grid, 4 spp: RMSE",
        "independent, 4 spp: RMSE",
        "stratified, 4 spp: RMSE",
    ] {
        assert!(out.contains(s), "{out}");
    }
    // Four 64 x 36 panels with 6-pixel gaps and a 30-pixel label band.
    assert_eq!(png_size(&d.join("a.png")), (4 * 64 + 5 * 6, 36 + 6 + 30));
    ok(
        d,
        &[
            "aliasing",
            "--width",
            "40",
            "--reference-spp",
            "0",
            "--samplers",
            "grid",
            "-o",
            "b.png",
        ],
    );
    assert_eq!(png_size(&d.join("b.png")), (40 + 2 * 6, 22 + 6 + 30));
}

#[test]
fn studies_refuse_bad_flags_before_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let c = ["converge", "--cache-dir", "cache", "--width", "32"];
    let with = |extra: &[&'static str]| [&c[..], extra].concat();
    for (extra, says) in [
        (&["--reference-spp", "2048"][..], "at least 16 x 256"),
        (
            &["--with-1024", "--reference-spp", "8192"],
            "at least 16 x 1024",
        ),
        (&["--pixel-bounds", "0,40,0,5"], "outside the 32x18 image"),
        (&["--pixel-bounds", "5,5,0,5"], "empty"),
        (&["--pixel-bounds", "1,2,3"], "x0,x1,y0,y1"),
        (&["--csv", "out.txt"], "must end in .csv"),
        (&["--plot", "out.jpg"], "must end in .png"),
        (&["--samplers", "nope"], "invalid value"),
        (&["--scene", "nope"], "unknown scene"),
    ] {
        let err = refused(d, &with(extra));
        assert!(err.contains(says), "{extra:?}: {err}");
    }
    for (args, says) in [
        (&["aliasing", "-o", "a.exr"][..], "must end in .png"),
        (&["aliasing", "--spp", "0"], "0 is not in 1"),
        (&["aliasing", "--samplers", "grid,nope"], "invalid value"),
    ] {
        let err = refused(d, args);
        assert!(err.contains(says), "{args:?}: {err}");
    }
}

/// The flags of a small cover render; `extra` and `-o name` follow.
fn cover_render(dir: &Path, name: &str, extra: &[&str]) {
    let mut args = vec![
        "render",
        "--scene",
        "cover",
        "--width",
        "40",
        "--spp",
        "6",
        "--seed",
        "3",
        "--max-depth",
        "6",
        "--sampler",
        "sobol",
    ];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["-o", name]);
    ok(dir, &args);
}

#[test]
fn split_renders_merge_into_the_one_shot_image() {
    // The box, and Lanczos, whose splatted parts hold the sums their
    // samples add beyond their windows.
    for filter in [&[][..], &["--filter", "lanczos"][..]] {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let render = |name: &str, extra: &[&str]| {
            let mut args = extra.to_vec();
            args.extend_from_slice(filter);
            cover_render(d, name, &args);
        };
        render("full.png", &[]);
        render("full.exr", &[]);
        // Pixels and samples both split, unevenly: left columns in two
        // sample runs, the right part by --crop (40 × 0.45 → column 18;
        // the image is 40 × 22), the bottom right rows in another run.
        render(
            "a.film",
            &["--pixel-bounds", "0,18,0,22", "--samples", "0..4"],
        );
        render(
            "b.film",
            &["--pixel-bounds", "0,18,0,22", "--samples", "4..6"],
        );
        render("c.film", &["--crop", "0.45,1,0,0.5"]);
        render("e.film", &["--crop", "0.45,1,0.5,1", "--threads", "1"]);
        let parts = ["e.film", "b.film", "c.film", "a.film"];
        let merge = |out: &str| {
            let mut args = vec!["merge"];
            args.extend_from_slice(&parts);
            args.extend_from_slice(&["-o", out]);
            ok(d, &args)
        };
        let said = merge("m.png");
        assert!(said.contains("merged 4 parts"), "{said}");
        assert_eq!(bytes(&d.join("m.png")), bytes(&d.join("full.png")), "PNG");
        merge("m.exr");
        assert_eq!(bytes(&d.join("m.exr")), bytes(&d.join("full.exr")), "EXR");
        // A merged film is a film too.
        merge("m.film");
        ok(d, &["merge", "m.film", "-o", "again.png"]);
        assert_eq!(bytes(&d.join("again.png")), bytes(&d.join("full.png")));
        // The film is 64 bytes a pixel and a short header.
        let film = bytes(&d.join("m.film")).len();
        assert!(
            (64 * 22 * 40..64 * 22 * 40 + 1024).contains(&film),
            "{film}"
        );
        // Staged: the left's two runs, then the right's two windows, then
        // the two halves; an image of a stage is refused.
        let said = ok(d, &["merge", "a.film", "b.film", "-o", "left.film"]);
        assert!(
            said.contains("a staged part: pixels 0,18,0,22, samples 0..6"),
            "{said}"
        );
        ok(d, &["merge", "c.film", "e.film", "-o", "right.film"]);
        let e = refused(d, &["merge", "c.film", "e.film", "-o", "right.png"]);
        assert!(
            e.contains("the parts leave a gap: pixel (0, 0) has 0 of its 6"),
            "{e}"
        );
        assert!(e.contains("a .film output may be a staged part"), "{e}");
        ok(d, &["merge", "right.film", "left.film", "-o", "staged.png"]);
        assert_eq!(bytes(&d.join("staged.png")), bytes(&d.join("full.png")));
        // A crop rendered straight to an image is the window's pixels of
        // the whole render.
        render("crop.png", &["--crop", "0.45,1,0,0.5"]);
        assert_eq!(png_size(&d.join("crop.png")), (22, 11));
        let (crop, full) = (png_rgb8(&d.join("crop.png")), png_rgb8(&d.join("full.png")));
        for (i, p) in crop.chunks(3).enumerate() {
            let (x, y) = (i % 22, i / 22);
            let at = 3 * (y * 40 + x + 18);
            assert_eq!(p, &full[at..at + 3], "{filter:?} ({x}, {y})");
        }
    }
    // pbrt's rule in f32: 0.2 × 10 rows is row 2, not 3.
    let dir = tempfile::tempdir().unwrap();
    ok(
        dir.path(),
        &[
            "render",
            "--width",
            "18",
            "--spp",
            "1",
            "--crop",
            "0,1,0,0.2",
            "-o",
            "band.png",
        ],
    );
    assert_eq!(png_size(&dir.path().join("band.png")), (18, 2));
}

#[test]
fn merge_refuses_overlaps_gaps_and_strangers() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    cover_render(d, "top.film", &["--pixel-bounds", "0,40,0,12"]);
    cover_render(d, "bottom.film", &["--pixel-bounds", "0,40,12,22"]);
    cover_render(
        d,
        "low.film",
        &["--pixel-bounds", "0,40,11,22", "--samples", "0..2"],
    );
    cover_render(
        d,
        "first.film",
        &["--pixel-bounds", "0,40,12,22", "--samples", "0..3"],
    );
    // Another seed, another size, another scene: the same bottom rows.
    let stranger = |scene: &str, width: &str, seed: &str, name: &str| {
        let args = [
            "render",
            "--scene",
            scene,
            "--width",
            width,
            "--spp",
            "6",
            "--seed",
            seed,
            "--max-depth",
            "6",
            "--sampler",
            "sobol",
            "--pixel-bounds",
            "0,40,12,22",
            "-o",
            name,
        ];
        ok(d, &args);
    };
    stranger("cover", "40", "4", "seed4.film");
    stranger("cover", "41", "3", "wide.film");
    stranger("week09", "40", "3", "week.film");
    let full = bytes(&d.join("bottom.film"));
    std::fs::write(d.join("cut.film"), &full[..full.len() - 100]).unwrap();
    let mut flipped = full.clone();
    let last = flipped.len() - 1;
    flipped[last] ^= 1;
    std::fs::write(d.join("flipped.film"), &flipped).unwrap();
    std::fs::write(d.join("notes.film"), "hello\nworld\n").unwrap();
    cover_render(d, "image.png", &[]);
    for (parts, want) in [
        (
            vec!["top.film", "low.film"],
            "`top.film` and `low.film` overlap",
        ),
        (
            vec!["top.film"],
            "gap: pixel (0, 12) has 0 of its 6 samples",
        ),
        (
            vec!["top.film", "first.film"],
            "gap: pixel (0, 12) has 3 of its 6",
        ),
        (
            vec!["top.film", "seed4.film"],
            "`seed4.film` is from another render than `top.film`: seed",
        ),
        (
            vec!["top.film", "wide.film"],
            "`wide.film` is from another render",
        ),
        (
            vec!["top.film", "week.film"],
            "`week.film` is from another render than `top.film`: scene",
        ),
        (vec!["top.film", "cut.film"], "`cut.film`: truncated"),
        (vec!["top.film", "flipped.film"], "`flipped.film`: corrupt"),
        (
            vec!["top.film", "notes.film"],
            "`notes.film`: not a Strata film",
        ),
        (
            vec!["top.film", "image.png"],
            "`image.png`: not a Strata film",
        ),
        (
            vec!["top.film", "missing.film"],
            "cannot read `missing.film`",
        ),
    ] {
        let mut args = vec!["merge"];
        args.extend_from_slice(&parts);
        args.extend_from_slice(&["-o", "out.png"]);
        let e = refused(d, &args);
        assert!(e.contains(want), "{parts:?}: {e}");
    }
    // A merge never overwrites one of its parts.
    let e = refused(d, &["merge", "top.film", "bottom.film", "-o", "top.film"]);
    assert!(e.contains("one of the parts"), "{e}");
    // The good pair merges.
    ok(d, &["merge", "top.film", "bottom.film", "-o", "out.png"]);
    assert_eq!(bytes(&d.join("out.png")), bytes(&d.join("image.png")));
}

#[test]
fn split_flags_are_checked_before_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (args, want) in [
        (
            vec!["render", "--spp", "4", "--samples", "3..3"],
            "--samples",
        ),
        (
            vec!["render", "--spp", "4", "--samples", "2..5"],
            "past the 4 samples",
        ),
        (vec!["render", "--samples", "x"], "--samples"),
        (vec!["render", "--crop", "0.5,0.5,0,1"], "--crop"),
        (vec!["render", "--crop", "0,2,0,1"], "--crop"),
        (vec!["render", "--crop", "0,1,0"], "--crop"),
        (
            vec!["render", "--crop", "0.95,0.96,0,1", "--width", "10"],
            "holds no pixel",
        ),
        (
            vec!["render", "--crop", "0,1,0,1", "--pixel-bounds", "0,1,0,1"],
            "cannot be used with",
        ),
        (
            vec!["render", "--width", "10", "--pixel-bounds", "0,11,0,1"],
            "outside",
        ),
        (vec!["render", "--stats", "facts.txt"], ".json"),
        (vec!["render", "-o", "x.jpg"], ".film"),
        (vec!["merge", "-o", "x.png"], "PARTS"),
        (vec!["merge", "a.film", "-o", "x.tif"], ".png or .exr"),
    ] {
        let e = refused(d, &args);
        assert!(e.contains(want), "{args:?}: {e}");
    }
}

#[test]
fn stats_hold_run_facts_and_images_do_not() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(
        d,
        &[
            "render",
            "--width",
            "24",
            "--spp",
            "2",
            "--threads",
            "1",
            "--stats",
            "s.json",
            "-o",
            "s.png",
        ],
    );
    let facts: serde_json::Value =
        serde_json::from_slice(&bytes(&d.join("s.json"))).expect("valid JSON");
    assert_eq!(facts["threads"], 1);
    assert!(facts["wall_seconds"].as_f64().unwrap() > 0.0);
    assert_eq!(facts["simd"], strata::trace::simd_level().name());
    assert_eq!(
        facts["integrator"],
        strata::render::Integrator::default().name()
    );
    assert_eq!(facts["camera_paths"], 24 * 13 * 2);
    let png = String::from_utf8_lossy(&bytes(&d.join("s.png"))).into_owned();
    assert!(png.contains("strata.version") && png.contains("strata.camera"));
    assert!(!png.contains("threads") && !png.contains("avx") && !png.contains("sse2"));
}

#[test]
fn verify_reproduces_the_golden_table() {
    let dir = tempfile::tempdir().unwrap();
    let out = ok(dir.path(), &["verify", "--threads", "2"]);
    let rows = strata_runner::golden::GOLDEN.len();
    assert_eq!(
        out.lines().filter(|l| l.starts_with("pass  ")).count(),
        rows,
        "{out}"
    );
    assert!(
        out.contains(&format!("all {rows} golden rows match")),
        "{out}"
    );
    assert!(listing(dir.path()).is_empty(), "verify writes no file");
}

/// The golden table's file rows are the bytes `strata render` writes: the
/// golden render of every built-in scene, through the command line, as
/// PNG, EXR and `.film`.
#[test]
fn golden_file_rows_are_what_render_writes() {
    use strata_runner::golden;
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = golden::SIZE;
    for scene in strata_runner::scenes::BUILT_IN {
        for ext in golden::FILE_FORMATS {
            let name = format!("{scene}.{ext}");
            ok(
                dir.path(),
                &[
                    "render",
                    "--scene",
                    scene,
                    "--width",
                    &w.to_string(),
                    "--height",
                    &h.to_string(),
                    "--spp",
                    &golden::SPP.to_string(),
                    "--seed",
                    &golden::SEED.to_string(),
                    "--max-depth",
                    &golden::DEPTH.to_string(),
                    "--sampler",
                    golden::FILE_SAMPLER.name(),
                    "--threads",
                    "1",
                    "-o",
                    &name,
                ],
            );
            let got = strata_runner::hash::fnv1a(&bytes(&dir.path().join(&name)));
            assert_eq!(
                Some(got),
                golden::expected(scene, &format!("file.{ext}")),
                "{name}"
            );
        }
    }
}

/// Renders `horizon` 48 pixels wide at `spp` with `extra` flags to `name`
/// in `dir`; returns the file's bytes.
fn horizon(dir: &Path, spp: &str, name: &str, extra: &[&str]) -> Vec<u8> {
    let mut args = vec![
        "render", "--scene", "horizon", "--width", "48", "--spp", spp,
    ];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["-o", name]);
    ok(dir, &args);
    bytes(&dir.join(name))
}

#[test]
fn filters_are_chosen_on_the_command_line_and_named_in_metadata() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let render = |name: &str, extra: &[&str]| horizon(d, "2", name, extra);
    let boxed = render("box.png", &[]);
    let mitchell = render("m.png", &["--filter", "mitchell"]);
    assert_ne!(boxed, mitchell);
    let text = String::from_utf8_lossy(&mitchell).into_owned();
    assert!(
        text.contains("mitchell r=2.0 b=0.33333334 c=0.33333334"),
        "metadata"
    );
    assert!(String::from_utf8_lossy(&boxed).contains("box r=0.5"));
    let wide = render(
        "t.png",
        &[
            "--filter",
            "tent",
            "--filter-radius",
            "2.5",
            "--threads",
            "1",
        ],
    );
    assert!(String::from_utf8_lossy(&wide).contains("tent r=2.5"));
    // Tiles stay independent with a wide filter.
    assert_eq!(
        render(
            "t2.png",
            &["--filter", "tent", "--filter-radius", "2.5", "--tile", "5"]
        ),
        wide
    );
    for (args, want) in [
        (vec!["render", "--filter", "sinc"], "--filter"),
        (
            vec!["render", "--filter", "tent", "--filter-radius", "9"],
            "radius must be in (0, 8]",
        ),
        (vec!["render", "--filter-radius", "0"], "--filter-radius"),
    ] {
        let e = refused(d, &args);
        assert!(e.contains(want), "{args:?}: {e}");
    }
}

#[test]
fn adaptive_renders_split_merge_and_write_an_spp_map() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let adaptive = ["--adaptive", "0.002", "--min-spp", "8", "--max-spp", "48"];
    // cover_render's flags but --spp, which --adaptive replaces.
    let render = |name: &str, extra: &[&str]| {
        let mut args = vec![
            "render",
            "--scene",
            "cover",
            "--width",
            "40",
            "--seed",
            "3",
            "--max-depth",
            "6",
            "--sampler",
            "sobol",
        ];
        args.extend_from_slice(&adaptive);
        args.extend_from_slice(extra);
        args.extend_from_slice(&["-o", name]);
        ok(d, &args)
    };
    let said = render("full.png", &["--spp-map", "map.png"]);
    assert!(said.contains("adaptive 8..48 spp at 0.002 (mean"), "{said}");
    render("full.exr", &[]);
    let full = String::from_utf8_lossy(&bytes(&d.join("full.png"))).into_owned();
    assert!(full.contains("threshold=0.002 min=8 max=48"), "metadata");
    // The map is the image's pixels with the legend under it (padded to
    // the legend's width), and varies: dark at the minimum, brighter
    // where pixels took more.
    use strata_runner::plot::{SPP_LEGEND_HEIGHT, SPP_LEGEND_MIN_WIDTH};
    let (w, h) = png_size(&d.join("full.png"));
    assert_eq!(
        png_size(&d.join("map.png")),
        (w.max(SPP_LEGEND_MIN_WIDTH), h + SPP_LEGEND_HEIGHT)
    );
    let map = strata_runner::image_io::read_png_linear(&d.join("map.png")).unwrap();
    let map_width = map.width as usize;
    let lum: Vec<f32> = (0..h as usize)
        .flat_map(|y| (0..w as usize).map(move |x| (x, y)))
        .map(|(x, y)| map.texels[y * map_width + x].y)
        .collect();
    let (lo, hi) = lum
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), &v| (a.min(v), b.max(v)));
    assert!(hi > lo + 0.2, "spp map from {lo} to {hi}");
    // Crops of an adaptive render merge into the one-shot image, and so
    // does its spp map.
    render("a.film", &["--crop", "0,0.5,0,1"]);
    render("b.film", &["--crop", "0.5,1,0,1", "--threads", "1"]);
    ok(
        d,
        &[
            "merge",
            "b.film",
            "a.film",
            "-o",
            "m.png",
            "--spp-map",
            "m-map.png",
        ],
    );
    assert_eq!(bytes(&d.join("m.png")), bytes(&d.join("full.png")));
    assert_eq!(bytes(&d.join("m-map.png")), bytes(&d.join("map.png")));
    ok(d, &["merge", "a.film", "b.film", "-o", "m.exr"]);
    assert_eq!(bytes(&d.join("m.exr")), bytes(&d.join("full.exr")));
    // Parts of a uniform render at the maximum spp are of another render.
    ok(
        d,
        &[
            "render",
            "--scene",
            "cover",
            "--width",
            "40",
            "--spp",
            "48",
            "--seed",
            "3",
            "--max-depth",
            "6",
            "--sampler",
            "sobol",
            "--crop",
            "0.5,1,0,1",
            "-o",
            "u.film",
        ],
    );
    // Bare --adaptive takes the documented defaults.
    let said = ok(
        d,
        &[
            "render",
            "--scene",
            "cover",
            "--width",
            "8",
            "--adaptive",
            "-o",
            "def.png",
        ],
    );
    let want = format!(
        "adaptive {}..{} spp at {} (mean",
        strata::render::Adaptive::DEFAULT_MIN,
        strata::render::Adaptive::DEFAULT_MAX,
        strata::render::Adaptive::DEFAULT_THRESHOLD
    );
    assert!(said.contains(&want), "{said}");
    let e = refused(d, &["merge", "a.film", "u.film", "-o", "x.png"]);
    assert!(e.contains("adaptive is `off`"), "{e}");
    let below = format!(
        "--max-spp 32 is below --min-spp 64 (default {})",
        strata::render::Adaptive::DEFAULT_MIN
    );
    for (args, want) in [
        (
            vec![
                "render",
                "--adaptive",
                "0.1",
                "--max-spp",
                "8",
                "--samples",
                "0..4",
            ],
            "--samples",
        ),
        (vec!["render", "--spp", "16", "--adaptive"], "--spp"),
        (vec!["render", "--max-spp", "64"], "--adaptive"),
        (vec!["render", "--min-spp", "64"], "--adaptive"),
        (vec!["render", "--adaptive", "0"], "positive"),
        (vec!["render", "--adaptive", "nan"], "positive"),
        (
            vec!["render", "--adaptive", "--min-spp", "10"],
            "--min-spp 10 must be a multiple of 4 of at least 8",
        ),
        (vec!["render", "--adaptive", "--min-spp", "4"], "not in 8.."),
        (
            vec!["render", "--adaptive", "--min-spp", "64", "--max-spp", "32"],
            below.as_str(),
        ),
        (vec!["render", "--spp-map", "m.png"], "--adaptive"),
        (
            vec![
                "render",
                "--sampler",
                "grid",
                "--adaptive",
                "0.1",
                "--max-spp",
                "256",
            ],
            "--adaptive needs a sampler whose first samples spread",
        ),
        (
            vec![
                "render",
                "--adaptive",
                "0.1",
                "--max-spp",
                "256",
                "--spp-map",
                "m.jpg",
            ],
            "must end in .png",
        ),
        (
            vec![
                "render",
                "--adaptive",
                "0.1",
                "--max-spp",
                "256",
                "--spp-map",
                "o.png",
                "-o",
                "o.png",
            ],
            "is the image's output",
        ),
        (
            vec![
                "merge",
                "a.film",
                "b.film",
                "-o",
                "y.png",
                "--spp-map",
                "a.film",
            ],
            "must end in .png",
        ),
    ] {
        let e = refused(d, &args);
        assert!(e.contains(want), "{args:?}: {e}");
    }
}

#[test]
fn texture_filter_is_chosen_on_the_command_line_and_named_in_metadata() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let render = |name: &str, extra: &[&str]| horizon(d, "1", name, extra);
    let point = render("p.png", &[]);
    let boxed = render("b.png", &["--texture-filter", "box"]);
    assert_ne!(point, boxed);
    assert_eq!(render("n.png", &["--texture-filter", "none"]), point);
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    assert!(
        text(&boxed).contains("strata.texture_filter\0box"),
        "metadata"
    );
    assert!(
        text(&point).contains("strata.texture_filter\0none"),
        "metadata"
    );
    // Tiles and threads do not change a prefiltered image.
    assert_eq!(
        render(
            "b2.png",
            &["--texture-filter", "box", "--tile", "5", "--threads", "1"]
        ),
        boxed
    );
    let said = ok(
        d,
        &[
            "aliasing",
            "--width",
            "48",
            "--spp",
            "1",
            "--reference-spp",
            "16",
            "--texture-filter",
            "box",
            "-o",
            "a.png",
        ],
    );
    assert!(said.contains("grid, 1 spp, prefiltered: RMSE"), "{said}");
    let e = refused(d, &["render", "--texture-filter", "trilinear"]);
    assert!(e.contains("--texture-filter"), "{e}");
}

#[test]
fn both_integrators_write_the_same_image() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let render = |name: &str, extra: &[&str]| horizon(d, "2", name, extra);
    let scalar = render("s.png", &["--integrator", "scalar", "--stats", "s.json"]);
    assert_eq!(render("l.png", &["--integrator", "lockstep"]), scalar);
    assert_eq!(render("d.png", &[]), scalar);
    let facts: serde_json::Value =
        serde_json::from_slice(&bytes(&d.join("s.json"))).expect("valid JSON");
    assert_eq!(facts["integrator"], "scalar", "the flag, not the default");
    let e = refused(d, &["render", "--integrator", "simd"]);
    assert!(e.contains("--integrator"), "{e}");
}

#[test]
fn spectrum_writes_an_image_a_plot_and_csv() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let said = ok(
        d,
        &[
            "spectrum",
            "--sampler",
            "independent,stratified",
            "--spp",
            "16",
            "--pixels",
            "64",
            "-o",
            "s.png",
        ],
    );
    assert!(
        said.contains("stratified   mean power below √spp"),
        "{said}"
    );
    let csv = String::from_utf8(bytes(&d.join("s-radial.csv"))).unwrap();
    assert!(
        csv.starts_with("frequency,independent,stratified\n1,"),
        "{csv}"
    );
    // Default range 16 for 16 spp: a row per radius.
    assert_eq!(csv.lines().count(), 17);
    assert_eq!(png_size(&d.join("s-radial.png")), (800, 480));
    let (w, h) = png_size(&d.join("s.png"));
    assert!(w > 2 * 33 * 7 && h > 33 * 7, "{w}x{h}");
    for (args, want) in [
        (vec!["spectrum", "--sampler", "sobel"], "--sampler"),
        (vec!["spectrum", "--spp", "0"], "--spp"),
        (
            vec!["spectrum", "--max-frequency", "129"],
            "--max-frequency",
        ),
        (vec!["spectrum", "-o", "s.jpg"], "must end in .png"),
        (
            vec!["spectrum", "-o", "t.png", "--csv", "t.txt"],
            "must end in .csv",
        ),
        (
            vec!["spectrum", "-o", "t.png", "--plot", "t.png"],
            "is the spectrum image",
        ),
    ] {
        let e = refused(d, &args);
        assert!(e.contains(want), "{args:?}: {e}");
    }
}

/// `--sampler zsobol`: the same bytes for any thread count and tile size,
/// sample runs merge into the one-shot image, the file names its sampler,
/// and a spp that is not a power of two is rendered as asked.
#[test]
fn zsobol_renders_split_and_merges_like_the_other_samplers() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let base = [
        "render",
        "--scene",
        "showcase",
        "--width",
        "48",
        "--spp",
        "4",
        "--sampler",
        "zsobol",
    ];
    let run = |name: &str, extra: &[&str]| {
        let mut args: Vec<&str> = base.to_vec();
        args.extend_from_slice(extra);
        args.extend_from_slice(&["-o", name]);
        ok(d, &args);
        bytes(&d.join(name))
    };
    let one = run("z1.png", &["--threads", "1"]);
    assert_eq!(run("z2.png", &["--threads", "2", "--tile", "5"]), one);
    let text = String::from_utf8_lossy(&one).into_owned();
    assert!(text.contains("zsobol"), "the metadata names the sampler");
    run("a.film", &["--samples", "0..3"]);
    run("b.film", &["--samples", "3..4"]);
    ok(d, &["merge", "b.film", "a.film", "-o", "m.png"]);
    assert_eq!(bytes(&d.join("m.png")), one);
    let said = ok(
        d,
        &[
            "render",
            "--scene",
            "showcase",
            "--width",
            "24",
            "--spp",
            "6",
            "--sampler",
            "zsobol",
            "-o",
            "six.png",
        ],
    );
    assert!(said.contains("6 spp (zsobol"), "{said}");
}

/// `converge --error-spectrum` on the example scene it is shown with: a
/// radial plot and its CSV of each point's error periodogram, and a table
/// of RMSE and low-band power as ratios to the first sampler; bad paths
/// are refused before any work.
#[test]
fn converge_error_spectrum_writes_plot_csv_and_ratios() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/scenes/soft-light.toml"
    );
    let said = ok(
        d,
        &[
            "converge",
            "--scene",
            scene,
            "--width",
            "32",
            "--pixel-bounds",
            "0,32,0,18",
            "--samplers",
            "sobol,zsobol",
            "--spps",
            "1,4",
            "--seeds",
            "2",
            "--reference-spp",
            "64",
            "--cache-dir",
            "cache",
            "--csv",
            "c.csv",
            "--plot",
            "c.png",
            "--error-spectrum",
            "e.png",
        ],
    );
    assert!(said.contains("ratios to sobol"), "{said}");
    for row in [
        "     1 sobol",
        "     1 zsobol",
        "     4 sobol",
        "     4 zsobol",
    ] {
        assert!(said.contains(row), "{row}: {said}");
    }
    assert_eq!(png_size(&d.join("e.png")), (800, 560));
    let csv = std::fs::read_to_string(d.join("e.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert_eq!(header, "frequency,sobol@1,sobol@4,zsobol@1,zsobol@4");
    // A row per ring that holds a frequency, each with a value per point.
    assert!(csv.lines().count() > 10, "{csv}");
    assert!(
        csv.lines().skip(1).all(|l| l.split(',').count() == 5),
        "{csv}"
    );
    let base = ["converge", "--cache-dir", "cache", "--width", "32"];
    for (extra, says) in [
        (&["--error-spectrum", "e.csv"][..], "must end in .png"),
        (
            &["--error-spectrum", "c.png", "--plot", "c.png"],
            "would overwrite --plot",
        ),
        (&["--spps", "0"], "0 is not in 1"),
        (&["--spps", "4", "--with-1024"], "cannot be used with"),
    ] {
        let err = refused(d, &[&base[..], extra].concat());
        assert!(err.contains(says), "{extra:?}: {err}");
    }
    // A long thin window is as costly as a square one of its side.
    let err = refused(
        d,
        &[
            "converge",
            "--cache-dir",
            "never",
            "--width",
            "1024",
            "--pixel-bounds",
            "0,1024,0,16",
            "--error-spectrum",
            "s.png",
        ],
    );
    assert!(err.contains("at most 512 pixels a side"), "{err}");
    let err = refused(
        d,
        &[
            "converge",
            "--cache-dir",
            "never",
            "--width",
            "32",
            "--pixel-bounds",
            "0,8,0,8",
            "--error-spectrum",
            "s.png",
        ],
    );
    assert!(err.contains("wider or taller than 8 pixels"), "{err}");
    // Refused before the reference is rendered: no cache was made.
    assert!(!d.join("never").exists());
    // Refused before any work: no file of the refused runs.
    for name in [
        "s.png",
        "s.csv",
        "converge-week09.csv",
        "converge-week09.png",
    ] {
        assert!(!d.join(name).exists(), "{name}");
    }
}

#[test]
fn adaptive_study_checks_its_flags_then_measures() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (args, want) in [
        (
            vec!["adaptive", "--csv", "x.txt"],
            "--csv `x.txt` must end in .csv",
        ),
        (
            vec!["adaptive", "--sampler", "grid"],
            "the grid fills its rows in order",
        ),
        (
            vec!["adaptive", "--min-spp", "12", "--max-spp", "8"],
            "--max-spp 8 is below --min-spp 12",
        ),
        (vec!["adaptive", "--threshold", "0"], "positive"),
        (vec!["adaptive", "--pixel-bounds", "0,400,0,10"], "outside"),
    ] {
        let e = refused(d, &args);
        assert!(e.contains(want), "{args:?}: {e}");
    }
    let said = ok(
        d,
        &[
            "adaptive",
            "--scene",
            "week09",
            "--width",
            "16",
            "--seeds",
            "2",
            "--min-spp",
            "8",
            "--max-spp",
            "32",
            "--threshold",
            "0.01",
            "--cache-dir",
            "cache",
            "--csv",
            "a.csv",
        ],
    );
    for want in [
        "2 seed(s); reference: sobol",
        "at equal rays: uniform RMSE",
        "bias: adaptive",
    ] {
        assert!(said.contains(want), "{want}: {said}");
    }
    let csv = std::fs::read_to_string(d.join("a.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("run,spp,rays_per_pixel,cpu_seconds,rmse,rel_mse")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert!(rows.len() >= 3, "{csv}");
    assert_eq!(rows[0][0], "adaptive");
    // The adaptive mean spp lies within its settings; every uniform row
    // took exactly its spp.
    let spp: f64 = rows[0][1].parse().unwrap();
    assert!((8.0..=32.0).contains(&spp), "{spp}");
    for r in &rows[1..] {
        assert_eq!(format!("uniform{}", r[1]), r[0]);
    }
}

#[test]
fn filter_study_checks_its_flags_then_measures_every_filter_against_the_box() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (args, want) in [
        (
            vec!["filters", "--csv", "x.txt"],
            "--csv `x.txt` must end in .csv",
        ),
        (
            vec!["filters", "--spps", "4,16", "--reference-spp", "128"],
            "--reference-spp 128 must be at least 16 times the largest of --spps (16)",
        ),
        (vec!["filters", "--spps", "0"], "not in 1.."),
        (vec!["filters", "--filters", "sinc"], "invalid value 'sinc'"),
        (vec!["filters", "--seeds", "0"], "not in 1.."),
        (vec!["filters", "--rounds", "0"], "not in 1.."),
    ] {
        // A cache inside the directory: a reference made before the
        // refusal would show as a file left behind.
        let mut args = args;
        args.extend(["--cache-dir", "cache"]);
        let e = refused(d, &args);
        assert!(e.contains(want), "{args:?}: {e}");
    }
    let said = ok(
        d,
        &[
            "filters",
            "--width",
            "24",
            "--spps",
            "4,1,4",
            "--seeds",
            "2",
            "--rounds",
            "2",
            "--reference-spp",
            "64",
            "--filters",
            "lanczos,tent,lanczos",
            "--cache-dir",
            "cache",
            "--csv",
            "f.csv",
        ],
    );
    assert!(
        said.contains("each filter against its own reference: sobol 64 spp"),
        "{said}"
    );
    let csv = std::fs::read_to_string(d.join("f.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some(
            "filter,spp,rmse,negative_noise,negative_near,negative_ringing,fallbacks,pixels,\
             mean_luminance,wall_seconds,time_vs_box,rmse_at_equal_time_vs_box"
        )
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // The box first at each spp (always measured), then the filters asked for.
    let names: Vec<(&str, &str)> = rows.iter().map(|r| (r[0], r[1])).collect();
    assert_eq!(
        names,
        [
            ("box r=0.5", "1"),
            ("lanczos r=3.0 tau=3.0", "1"),
            ("tent r=1.0", "1"),
            ("box r=0.5", "4"),
            ("lanczos r=3.0 tau=3.0", "4"),
            ("tent r=1.0", "4"),
        ]
    );
    for r in &rows {
        // 24x13 pixels, 2 seeds; errors and luminances are measured.
        assert_eq!(r[7], "624", "{r:?}");
        let rmse: f64 = r[2].parse().unwrap();
        assert!(rmse > 0.0 && rmse < 1.0, "{r:?}");
        assert!(r[8].parse::<f64>().unwrap() > 0.0, "{r:?}");
    }
    // The box against itself is 1, in time and at equal time.
    for r in rows.iter().filter(|r| r[0].starts_with("box")) {
        assert_eq!((r[10], r[11]), ("1", "1"), "{r:?}");
    }
    // The other filters render with their own filter (another error than
    // the box's) and were timed against it.
    for pair in rows.chunks(3) {
        for r in &pair[1..] {
            assert_ne!(r[2], pair[0][2], "{r:?}");
            let t: f64 = r[10].parse().unwrap();
            assert!(t.is_finite() && t > 0.0, "{r:?}");
            let eq: f64 = r[11].parse().unwrap();
            assert!(eq.is_finite() && eq > 0.0, "{r:?}");
        }
    }
    // Each reference was cached under the filter it was made with.
    assert_eq!(std::fs::read_dir(d.join("cache")).unwrap().count(), 3);
}

/// The phases of a command's `STRATA_PROGRESS=lines` report, in order of
/// their first line: (name, percentages reported, its closing line's
/// share).
fn phases(stderr: &str) -> Vec<(String, Vec<u32>, Option<u32>)> {
    let mut out: Vec<(String, Vec<u32>, Option<u32>)> = Vec::new();
    for line in stderr.lines() {
        let Some((name, rest)) = line.rsplit_once(": ") else {
            continue;
        };
        // `NAME: P %` or `NAME: P %, done in S s`; other lines are not
        // progress.
        let Some((Ok(share), tail)) = rest.split_once(" %").map(|(p, t)| (p.parse::<u32>(), t))
        else {
            continue;
        };
        let done = tail.starts_with(", done in");
        let name = name.to_string();
        let at = match out.iter().position(|p| p.0 == name) {
            Some(i) => i,
            None => {
                out.push((name, vec![], None));
                out.len() - 1
            }
        };
        match done {
            true => out[at].2 = Some(share),
            false => out[at].1.push(share),
        }
    }
    out
}

/// Every phase of a long command reports from 0 % up, in order, and ends
/// at 100 % (every unit it counts is counted): the studies that were
/// silent for minutes, and a render.
#[test]
fn long_commands_report_progress_phase_by_phase() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let run = |args: &[&str]| -> String {
        let out = Command::new(env!("CARGO_BIN_EXE_strata"))
            .args(args)
            .current_dir(d)
            .env("STRATA_PROGRESS", "lines")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{args:?}: {err}");
        err
    };
    let cases: [(&[&str], &[&str]); 6] = [
        (
            &["spectrum", "--spp", "4", "--pixels", "64", "-o", "s.png"],
            &["periodograms: 6 samplers over 64 pixels"],
        ),
        (
            &[
                "converge",
                "--width",
                "48",
                "--spps",
                "1,4",
                "--reference-spp",
                "64",
                "--samplers",
                "sobol,independent",
                "--cache-dir",
                "c1",
            ],
            &["reference: sobol 64 spp", "measuring:"],
        ),
        (
            &[
                "aliasing",
                "--width",
                "32",
                "--reference-spp",
                "16",
                "-o",
                "a.png",
            ],
            &["panels:", "reference: sobol 16 spp"],
        ),
        (
            &[
                "adaptive",
                "--width",
                "32",
                "--seeds",
                "1",
                "--min-spp",
                "8",
                "--max-spp",
                "16",
                "--cache-dir",
                "c2",
            ],
            &[
                "adaptive: 1 render",
                "reference: sobol",
                "uniform ",
                "CPU seconds:",
            ],
        ),
        (
            &[
                "filters",
                "--width",
                "32",
                "--spps",
                "1",
                "--seeds",
                "1",
                "--rounds",
                "1",
                "--reference-spp",
                "16",
                "--filters",
                "tent",
                "--cache-dir",
                "c3",
            ],
            &["reference: sobol 16 spp", "1 spp:"],
        ),
        (
            &["render", "--width", "32", "--spp", "2", "-o", "r.png"],
            &["render week09"],
        ),
    ];
    for (args, want) in cases {
        let err = run(args);
        let got = phases(&err);
        let mut at = 0;
        for w in want {
            let k = got[at..]
                .iter()
                .position(|p| p.0.starts_with(w))
                .unwrap_or_else(|| panic!("{args:?}: no phase `{w}` (in order) in\n{err}"));
            at += k;
        }
        for (name, shares, end) in &got {
            assert_eq!(
                shares.first(),
                Some(&0),
                "{args:?} {name}: starts at 0 %\n{err}"
            );
            assert!(
                shares.windows(2).all(|w| w[0] < w[1]),
                "{args:?} {name}: rises\n{err}"
            );
            assert_eq!(*end, Some(100), "{args:?} {name}: ends complete\n{err}");
        }
    }
    // Without the variable and without a terminal: nothing drawn.
    let out = strata(d, &["render", "--width", "32", "--spp", "2", "-o", "q.png"]);
    assert!(String::from_utf8_lossy(&out.stderr).trim().is_empty());
}

/// A study stopped after its reference keeps it: the reference's phase
/// ends only once it is stored, and the next run reads it from the cache.
#[test]
fn an_interrupted_study_keeps_its_finished_reference() {
    use std::io::BufRead;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = [
        "converge",
        "--width",
        "96",
        "--spps",
        "1,4,16,64",
        "--seeds",
        "4",
        "--reference-spp",
        "1024",
        "--cache-dir",
        "cache",
    ];
    let mut child = Command::new(env!("CARGO_BIN_EXE_strata"))
        .args(args)
        .current_dir(d)
        .env("STRATA_PROGRESS", "lines")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let err = std::io::BufReader::new(child.stderr.take().unwrap());
    let mut seen = String::new();
    for line in err.lines() {
        let line = line.unwrap();
        seen.push_str(&line);
        seen.push('\n');
        if line.starts_with("reference: ") && line.contains("done in") {
            break;
        }
    }
    // Killed at once (it may have finished meanwhile on a fast machine:
    // the reference must be kept either way).
    child.kill().ok();
    child.wait().unwrap();
    assert!(seen.contains("done in"), "{seen}");
    let cached: Vec<_> = std::fs::read_dir(d.join("cache")).unwrap().collect();
    assert_eq!(cached.len(), 1, "{seen}");
    let out = ok(d, &args[..]);
    assert!(out.contains("reference: sobol 1024 spp, cached"), "{out}");
}
