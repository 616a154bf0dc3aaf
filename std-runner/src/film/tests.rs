//! Films through their bytes and through merges: round trips, damaged and
//! hostile files, adaptive sample counts, parts of another render.

use std::ops::Range;
use std::path::PathBuf;

use strata::render::{PixelSum, Tile};

use super::key::parse_filter;
use super::{Film, KEY_FIELDS, RenderKey, filter_text, merge, merge_whole};

fn film(width: u32, height: u32, window: Tile, samples: Range<u32>) -> Film {
    let job_key = |k: &str| match k {
        "version" => super::version(),
        "scene" => "test".to_string(),
        "scene_hash" => "0123456789abcdef".to_string(),
        "camera" => "from [0.0, 1.0, 2.0] at [0.0, 0.0, 0.0] up [0.0, 1.0, 0.0] vfov 40.0 \
                     defocus 0.0 focus 2.236068"
            .to_string(),
        "size" => format!("{width}x{height}"),
        "spp" => "8".to_string(),
        "sampler" => "sobol".to_string(),
        "seed" => "7".to_string(),
        "max_depth" => "5".to_string(),
        "direct_lighting" => "true".to_string(),
        "adaptive" => "off".to_string(),
        "filter" => "box r=0.5".to_string(),
        "texture_filter" => "none".to_string(),
        _ => unreachable!("{k} is not a key field"),
    };
    let n = samples.end - samples.start;
    Film {
        key: RenderKey {
            fields: KEY_FIELDS.iter().map(|&k| (k, job_key(k))).collect(),
            width,
            height,
            spp: 8,
            adaptive: None,
        },
        window,
        border: 0,
        pixels: (0..window.area())
            .map(|i| PixelSum {
                sum: [i as i64, -(i as i64), 1 << 40],
                weight: (n as i64 - 1) << 24,
                own_minus_sum: [2 * i as i64, 5, -(1 << 41)],
                samples: n - 1,
                dropped: 1,
            })
            .collect(),
        samples,
    }
}

fn tile(x0: u32, y0: u32, width: u32, height: u32) -> Tile {
    Tile {
        x0,
        y0,
        width,
        height,
    }
}

#[test]
fn films_round_trip_through_bytes() {
    let f = film(7, 5, tile(2, 1, 3, 4), 2..5);
    assert_eq!(Film::from_bytes(&f.to_bytes()).unwrap(), f);
}

fn refused(bytes: &[u8]) -> String {
    format!("{:#}", Film::from_bytes(bytes).unwrap_err())
}

/// The bytes with the header's checksum written again after an edit (as
/// a tool that meant the edit would): what lies behind it is reached.
fn reseal(bytes: &[u8]) -> Vec<u8> {
    let end = bytes.windows(2).position(|w| w == b"\n\n").unwrap();
    let last = bytes[..end].iter().rposition(|&b| b == b'\n').unwrap() + 1;
    let mut out = bytes[..last].to_vec();
    let sum = crate::hash::fnv1a(&out);
    out.extend_from_slice(format!("head_checksum={sum:016x}").as_bytes());
    out.extend_from_slice(&bytes[end..]);
    out
}

/// The film's bytes with `from` replaced by `to` in the header, resealed.
fn edited(bytes: &[u8], from: &str, to: &str) -> Vec<u8> {
    let t = String::from_utf8_lossy(bytes).into_owned();
    let (head, _) = t.split_once("\n\n").unwrap();
    assert!(head.contains(from), "{from}");
    let mut out = head.replacen(from, to, 1).into_bytes();
    out.extend_from_slice(b"\n\n");
    out.extend_from_slice(&bytes[head.len() + 2..]);
    reseal(&out)
}

#[test]
fn damaged_or_hostile_films_are_refused() {
    let good = film(7, 5, tile(2, 1, 3, 4), 2..5).to_bytes();
    let edit = |from: &str, to: &str| edited(&good, from, to);
    // A huge size would make a merge allocate it.
    let e = refused(&edit("size=7x5", "size=4000000000x4000000000"));
    assert!(e.contains("beyond what strata renders"), "{e}");
    let e = refused(&edit("size=7x5", "size=4x5"));
    assert!(e.contains("outside the 4x5 image"), "{e}");
    let e = refused(&edit("samples=2..5", "samples=2..9"));
    assert!(e.contains("exceed spp 8"), "{e}");
    let e = refused(&edit("samples=2..5", "samples=1..5"));
    assert!(
        e.contains("holds 3 samples where the range 1..5 has 4"),
        "{e}"
    );
    let e = refused(&edit("window=2,5,1,5", "window=5,2,1,5"));
    assert!(e.contains("bad `window`"), "{e}");
    let e = refused(&edit("seed=7\n", ""));
    assert!(e.contains("no `seed`"), "{e}");
    let e = refused(&good[..good.len() - 1]);
    assert!(e.contains("truncated"), "{e}");
    let e = refused(&good[..40]);
    assert!(e.contains("truncated"), "{e}");
    let e = refused(&reseal(b"strata-film 5\nx\n\nxyz"));
    assert!(e.contains("no `version`"), "{e}");
    let e = refused(&edit("seed=7", "seed=7\nseed=9"));
    assert!(e.contains("repeats `seed`"), "{e}");
    for old in [
        &b"strata-film 1\n"[..],
        b"strata-film 2\n",
        b"strata-film 3\n",
        b"strata-film 4\nversion=0.1.0+r13\n\n",
    ] {
        let e = refused(old);
        assert!(
            e.contains("another format version") && e.contains("this build reads `strata-film 5`"),
            "{e}"
        );
    }
    let e = refused(b"");
    assert!(e.contains("not a Strata film"), "{e}");
}

#[test]
fn adaptive_films_hold_counts_from_the_minimum_to_the_maximum() {
    // min 8, max 16: blocks of 2, so 8, 10, …, 16 samples.
    let mut f = film(7, 5, tile(2, 1, 3, 4), 0..16);
    f.key.spp = 16;
    for (name, value) in f.key.fields.iter_mut() {
        match *name {
            "spp" => *value = "16".into(),
            "adaptive" => *value = "threshold=0.05 min=8 max=16".into(),
            _ => {}
        }
    }
    f.key.adaptive = Some(strata::render::Adaptive::new(8, 16, 0.05).unwrap());
    for (i, p) in f.pixels.iter_mut().enumerate() {
        p.samples = 7 + 2 * (i as u32 % 5); // 8 to 16 with the dropped one
    }
    assert_eq!(Film::from_bytes(&f.to_bytes()).unwrap(), f);
    let adaptive_field = f.key.fields.iter().position(|x| x.0 == "adaptive").unwrap();
    // Below the minimum, or not a whole block.
    for bad in [4, 8, 10] {
        let mut odd = f.clone();
        odd.pixels[3].samples = bad; // 5, 9 or 11 taken
        let e = refused(&odd.to_bytes());
        let want = format!(
            "holds {} samples where the range 0..16 has a multiple of 2 from 8 to 16",
            bad + 1
        );
        assert!(e.contains(&want), "{e}");
        // Built in code, the merge checks the same.
        let names = [PathBuf::from("odd")];
        let e = format!("{:#}", merge(&[odd], &names).unwrap_err());
        assert!(e.contains(&want), "{e}");
    }
    let mut part = f.clone();
    part.samples = 0..8;
    let e = refused(&part.to_bytes());
    assert!(e.contains("must cover samples 0..16 with max=16"), "{e}");
    let mut other = f.clone();
    other.key.fields[adaptive_field].1 = "threshold=0.05 min=8 max=12".into();
    let e = refused(&other.to_bytes());
    assert!(e.contains("with max=12"), "{e}");
    for bad in [
        "threshold=-1 min=8 max=16",
        "threshold=0.05 min=4 max=16",
        "threshold=0.05 min=10 max=16",
        "threshold=0.05 base=8 max=16",
    ] {
        other.key.fields[adaptive_field].1 = bad.into();
        let e = refused(&other.to_bytes());
        assert!(e.contains("bad `adaptive`"), "{bad}: {e}");
    }
}

#[test]
fn merge_names_the_first_differing_field() {
    let a = film(4, 2, tile(0, 0, 2, 2), 0..8);
    let mut b = film(4, 2, tile(2, 0, 2, 2), 0..8);
    b.key.fields[3].1 = "another camera".into();
    let names = [PathBuf::from("a"), PathBuf::from("b")];
    let e = merge(&[a.clone(), b], &names).unwrap_err().to_string();
    assert!(
        e.contains("`b` is from another render than `a`: camera"),
        "{e}"
    );
    let ok = merge(&[a.clone(), film(4, 2, tile(2, 0, 2, 2), 0..8)], &names).unwrap();
    assert_eq!(ok.pixels[0], a.pixels[0]);
    assert_eq!(ok.window, tile(0, 0, 4, 2));
}

/// Mitchell–Netravali (B = C = ⅓) of radius `r` splats with a border of
/// ⌈r + ½⌉ − 1.
fn mitchell(r: f32) -> String {
    format!("mitchell r={r:?} b={:?} c={:?}", 1.0f32 / 3.0, 1.0f32 / 3.0)
}

/// `f` as a render of Mitchell–Netravali of radius `r`, with its border:
/// border pixels hold sums, no samples.
fn with_border(mut f: Film, r: f32) -> Film {
    let old = f.window;
    let at = f.key.fields.iter().position(|x| x.0 == "filter").unwrap();
    f.key.fields[at].1 = mitchell(r);
    f.border = f.key.border().unwrap();
    let e = f.extent();
    f.pixels = (0..e.area())
        .map(|i| {
            let (x, y) = (e.x0 + i as u32 % e.width, e.y0 + i as u32 / e.width);
            let own = (old.x0..old.x0 + old.width).contains(&x)
                && (old.y0..old.y0 + old.height).contains(&y);
            let n = f.samples.end - f.samples.start;
            PixelSum {
                sum: [x as i64, y as i64, 3],
                weight: 1 << 20,
                own_minus_sum: if own { [y as i64, 7, x as i64] } else { [0; 3] },
                samples: if own { n } else { 0 },
                dropped: 0,
            }
        })
        .collect();
    f
}

#[test]
fn bordered_films_round_trip_and_check_their_border() {
    // A window at the image's left edge: the border is clipped there.
    let f = with_border(film(9, 6, tile(0, 2, 3, 2), 2..5), 2.0);
    assert_eq!(f.border, 2);
    assert_eq!(f.extent(), tile(0, 0, 5, 6));
    assert_eq!(f.window_pixels().len(), 6);
    let bytes = f.to_bytes();
    assert!(String::from_utf8_lossy(&bytes).contains("\nborder=2\n"));
    assert_eq!(Film::from_bytes(&bytes).unwrap(), f);
    // No border line without a border: a box film's bytes are as before.
    let plain = film(9, 6, tile(0, 2, 3, 2), 2..5).to_bytes();
    assert!(!String::from_utf8_lossy(&plain).contains("border="));
    // A border pixel that claims samples, and a border no filter has.
    let mut bad = f.clone();
    bad.pixels[0].samples = 1;
    let e = refused(&bad.to_bytes());
    assert!(
        e.contains("pixel (0, 0) of the border holds 1 samples"),
        "{e}"
    );
    let e = refused(&edited(&bytes, "border=2", "border=3"));
    assert!(
        e.contains("a border of 3 pixels where the render's filter (`mitchell r=2.0"),
        "{e}"
    );
    assert!(e.contains(") reaches 2"), "{e}");
    assert!(refused(&edited(&bytes, "border=2", "border=x")).contains("bad `border`: `x`"));
    let mut boxed = film(9, 6, tile(0, 2, 3, 2), 2..5);
    boxed.border = 2;
    let e = format!("{:#}", merge(&[boxed], &[PathBuf::from("b")]).unwrap_err());
    assert!(e.contains("`b` is inconsistent: a border of 2 pixels where the render's filter (`box r=0.5`) reaches 0"), "{e}");
    // Its window is no image yet: its edge pixels miss their neighbours.
    let e = f
        .output_bytes(
            std::path::Path::new("x.png"),
            crate::image_io::Transfer::Srgb,
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("merge it with the parts around it"), "{e}");
}

#[test]
fn staged_merges_join_cells_into_one_window_and_range() {
    // Four quadrants of an 8 × 6 image, samples 0..8, in two halves of
    // the samples for the top-left one; borders of 1.
    let q = |x0, y0, s: Range<u32>| with_border(film(8, 6, tile(x0, y0, 4, 3), s), 1.0);
    let parts = [
        q(0, 0, 0..4),
        q(0, 0, 4..8),
        q(4, 0, 0..8),
        q(0, 3, 0..8),
        q(4, 3, 0..8),
    ];
    let names: Vec<PathBuf> = (0..parts.len())
        .map(|i| PathBuf::from(format!("p{i}")))
        .collect();
    let whole = merge(&parts, &names).unwrap();
    assert_eq!(
        (whole.window, whole.samples.clone()),
        (tile(0, 0, 8, 6), 0..8)
    );
    // The top row, then the top-left's two halves first: the same film
    // in the end, bit for bit, whatever the tree.
    let left = merge(&parts[..2], &names[..2]).unwrap();
    assert_eq!(
        (left.window, left.samples.clone()),
        (tile(0, 0, 4, 3), 0..8)
    );
    assert_eq!(left.extent(), tile(0, 0, 5, 4));
    let top = merge(&[left, parts[2].clone()], &names[..2]).unwrap();
    assert_eq!(top.window, tile(0, 0, 8, 3));
    let again = merge(&[top, parts[3].clone(), parts[4].clone()], &names[..3]).unwrap();
    assert_eq!(again, whole);
    // Border sums land in the neighbour: pixel (4, 0) of the whole image
    // holds its own part's sums and the top-left parts' border sums.
    let at = |f: &Film, x: usize, y: usize| f.pixels[y * f.extent().width as usize + x];
    let own = at(&parts[2], 0, 0).weight;
    let from_left = at(&parts[0], 4, 0).weight + at(&parts[1], 4, 0).weight;
    assert_eq!(at(&whole, 4, 0).weight, own + from_left);
    // Cells that do not join into one window × range are refused.
    let e = merge(&[parts[0].clone(), parts[2].clone()], &names[..2])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("leave a gap in the window x 0..8, y 0..3"),
        "{e}"
    );
    assert!(e.contains("pixel (0, 0) has 4 of those 8 samples"), "{e}");
    let e = merge(&[parts[0].clone(), parts[3].clone()], &names[..2])
        .unwrap_err()
        .to_string();
    assert!(e.contains("a staged merge must join"), "{e}");
    // Spanning the whole image, the gap says the staged rule too.
    let e = merge(&[parts[0].clone(), parts[4].clone()], &names[..2])
        .unwrap_err()
        .to_string();
    assert!(e.contains("pixel (0, 0) has 4 of those 8 samples"), "{e}");
    assert!(e.contains("the whole render needs every part"), "{e}");
    // An image needs the whole render.
    let e = merge_whole(&[parts[0].clone(), parts[4].clone()], &names[..2])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("the parts leave a gap: pixel (0, 0) has 4 of its 8"),
        "{e}"
    );
    // Another border comes from another filter: another render.
    let e = merge(
        &[
            parts[2].clone(),
            with_border(film(8, 6, tile(0, 0, 4, 3), 0..8), 2.0),
        ],
        &names[..2],
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("`p1` is from another render than `p0`: filter"),
        "{e}"
    );
}

#[test]
fn filter_texts_parse_back_to_their_filters() {
    use strata::filter::{FilterKind, PixelFilter};
    for kind in FilterKind::ALL {
        for r in [kind.default_radius(), 2.7, 0.3] {
            let Ok(f) = PixelFilter::new(kind, r) else {
                continue;
            };
            assert_eq!(parse_filter(&filter_text(&f)), Some(f), "{kind:?} r={r}");
        }
    }
    for bad in [
        "",
        "box",
        "box r=x",
        "lanczos r=3.0",
        "box r=0.5 extra",
        "sinc r=1.0",
    ] {
        assert_eq!(parse_filter(bad), None, "{bad}");
    }
}

#[test]
fn file_merges_stream_bodies_and_match_in_memory_merges() {
    // Parts larger than a read chunk (16 Ki pixels), with borders, so
    // chunks end mid-row and border sums cross parts.
    let q = |x0, y0, s: Range<u32>| with_border(film(300, 140, tile(x0, y0, 150, 70), s), 1.0);
    let parts = [
        q(0, 0, 0..3),
        q(0, 0, 3..8),
        q(150, 0, 0..8),
        q(0, 70, 0..8),
        q(150, 70, 0..8),
    ];
    let dir = tempfile::tempdir().unwrap();
    let names: Vec<PathBuf> = (0..parts.len())
        .map(|i| dir.path().join(format!("p{i}.film")))
        .collect();
    for (p, n) in parts.iter().zip(&names) {
        std::fs::write(n, p.to_bytes()).unwrap();
    }
    let want = merge(&parts, &names).unwrap();
    assert_eq!(super::merge_files(&names, false).unwrap(), want);
    assert_eq!(super::merge_files(&names, true).unwrap(), want);
    // A staged subset, and the image rule.
    assert_eq!(
        super::merge_files(&names[..3], false).unwrap(),
        merge(&parts[..3], &names[..3]).unwrap()
    );
    let e = format!("{:#}", super::merge_files(&names[..3], true).unwrap_err());
    assert!(e.contains("an image needs the whole render"), "{e}");
    // A flipped byte deep in a body (past the first chunk) is found.
    let mut bytes = std::fs::read(&names[3]).unwrap();
    let at = bytes.len() - 100;
    bytes[at] ^= 1;
    std::fs::write(&names[3], &bytes).unwrap();
    let e = format!("{:#}", super::merge_files(&names, false).unwrap_err());
    assert!(
        e.contains("p3.film") && e.contains("checksum does not match"),
        "{e}"
    );
    // A body one record short is refused from its header, before any
    // body is read.
    std::fs::write(&names[3], &bytes[..bytes.len() - 64]).unwrap();
    let e = format!("{:#}", super::merge_files(&names, false).unwrap_err());
    assert!(
        e.contains("p3.film") && e.contains("truncated or padded"),
        "{e}"
    );
}

#[test]
fn header_values_are_clipped_in_messages() {
    let f = film(7, 5, tile(2, 1, 3, 4), 2..5);
    let bytes = f.to_bytes();
    let with_spp = |n: usize| edited(&bytes, "spp=8", &format!("spp={}", "9".repeat(n)));
    let e = refused(&with_spp(10_000));
    assert!(e.contains("bad `spp`") && e.len() < 300, "{e:.300}");
    let e = refused(&with_spp(100_000));
    assert!(e.contains("header is longer than 64 KB"), "{e:.300}");
    let mut other = f.clone();
    other.key.fields[1].1 = "x".repeat(100_000);
    let names = [PathBuf::from("a"), PathBuf::from("b")];
    let e = merge(&[f, other], &names).unwrap_err().to_string();
    assert!(e.contains("(100000 bytes)") && e.len() < 400, "{}", e.len());
}

/// Every header byte is covered by the header's checksum, and behind it
/// every field is parsed as its type: free text that a merge would copy
/// into an image's metadata is refused, and so is a film of another
/// build, even when the parts agree with each other.
#[test]
fn headers_are_sealed_and_typed() {
    let good = film(7, 5, tile(2, 1, 3, 4), 2..5).to_bytes();
    Film::from_bytes(&good).unwrap();
    let head = good.windows(2).position(|w| w == b"\n\n").unwrap();
    for at in MAGIC_LEN + 1..head {
        let mut bad = good.clone();
        bad[at] ^= 0x04;
        let e = refused(&bad);
        assert!(
            e.contains("header's checksum does not match") || e.contains("truncated"),
            "byte {at}: {e}"
        );
    }
    for (from, to, want) in [
        ("seed=7", "seed=hello", "bad `seed`: `hello`"),
        ("seed=7", "seed=07", "bad `seed`: `07`"),
        (
            "texture_filter=none",
            "texture_filter=banana",
            "bad `texture_filter`",
        ),
        ("sampler=sobol", "sampler=magic", "bad `sampler`"),
        (
            "direct_lighting=true",
            "direct_lighting=yes",
            "bad `direct_lighting`",
        ),
        (
            "scene_hash=0123456789abcdef",
            "scene_hash=0123456789ABCDEF",
            "bad `scene_hash`",
        ),
        ("max_depth=5", "max_depth=-5", "bad `max_depth`"),
        ("max_depth=5", "max_depth=0", "bad `max_depth`"),
        ("max_depth=5", "max_depth=4294967295", "bad `max_depth`"),
        ("vfov 40.0", "vfov NaN", "bad `camera`"),
        ("vfov 40.0", "vfov 180.0", "bad `camera`"),
        ("vfov 40.0", "vfov 40", "bad `camera`"),
        ("filter=box r=0.5", "filter=box r=0.50", "bad `filter`"),
        ("scene=test", "scene=", "bad `scene`"),
        (
            "seed=7",
            "seed=7\ncolour=red",
            "a field this build does not write: `colour`",
        ),
    ] {
        let e = refused(&edited(&good, from, to));
        assert!(e.contains(want), "{to}: {e}");
    }
    let v = format!("version={}", super::version());
    let e = refused(&edited(&good, &v, "version=9.9.9+r99"));
    assert!(
        e.contains("made by strata 9.9.9+r99, and this is strata") && e.contains(&super::version()),
        "{e}"
    );
}

const MAGIC_LEN: usize = super::MAGIC.len();
