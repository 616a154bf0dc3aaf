//! Checkpoints: the tiles a `strata render` has finished, kept on disk as
//! it goes, so an interrupted render (Ctrl-C, a killed job, a full disk at
//! the end) resumes where it stopped and ends in the same bytes.
//!
//! The file is a text header and then one record per finished tile,
//! appended as each tile finishes:
//!
//! ```text
//! strata-checkpoint 2
//! args=<the render's flags as JSON; paths below the checkpoint's
//!      directory relative to it, others absolute>
//! version=...              the RenderKey fields of the render, then
//! window=x0,x1,y0,y1       its pixel window, sample range and tiling:
//! samples=A..B
//! tile=N                   tile side
//! tiles=N                  tile count
//! head_checksum=<16 hex>   FNV-1a 64 of every header byte before this
//!                          line: the render's id
//!                          (an empty line ends the header)
//! record: b"TILE", the render's id u64, tile index u32, pixel count u32,
//!         paths, rays and shadow rays u64, the tile's film (64-byte
//!         pixel records as in a .film body), FNV-1a 64 of the record's
//!         preceding bytes; little-endian.
//! ```
//!
//! A record is complete or it is not there: a process killed while
//! appending leaves a record whose length or checksum is wrong, and
//! reading stops before it (and cuts it off before appending more). So a
//! killed render leaves only its checkpoint, and every tile the file holds
//! whole is never rendered again. The header is written to a temporary
//! file and renamed into place before the first tile starts.
//!
//! Damage is reported as damage, never acted on: a header whose checksum
//! fails is refused before any of it is used (its flags pass the one
//! check of [`RenderArgs::validate`] after that too), a whole record of
//! another render (another id) is refused, and every record's pixels are
//! checked as a `.film` body's are (each pixel of the tile took the
//! range's samples, each pixel of a splat margin none).
//!
//! Paths below the checkpoint's directory are kept relative to it, so a
//! job directory that is moved (or copied to another machine) resumes
//! with its files where they now are.

use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use strata::render::{PixelSum, Tile, TileStats};

use crate::cli::RenderArgs;
use crate::film::{
    BYTES_PER_PIXEL, RenderKey, count_problem, decode_pixels, encode_pixels, samples_text,
    window_text,
};
use crate::image_io::{write_atomic, write_file};
use crate::job::{Job, TileFilm, job_tiles, tile_film_len, tile_side};

/// The first line of every checkpoint.
pub const MAGIC: &str = "strata-checkpoint 2";

/// How often appended tiles are flushed to the disk itself (`fsync`), in
/// seconds; also on an interrupt and at the end. A killed process loses
/// nothing it appended either way (the kernel holds it); this bounds what
/// a machine crash loses.
pub const SYNC_SECONDS: u64 = 30;

/// The environment variable of the crash tests (a test hook, not a
/// setting): `after:N` aborts the process once the Nth tile of this run is
/// appended, `writing:N` halfway through appending it (as a kill would);
/// `hold:N` holds every append after the Nth until [`STOP`] is set, so a
/// test's signal finds the render running whatever the machine's speed;
/// `stuck:N` holds them for good (a tile that never ends), so a second
/// signal finds it still running.
pub const TEST_HOOK_VAR: &str = "STRATA_TEST_HOOK";

/// Set by the first SIGINT or SIGTERM of a checkpointed render (the
/// handler is `strata render`'s): no new tile starts.
pub static STOP: AtomicBool = AtomicBool::new(false);

/// Longest checkpoint header read (the flags and the render's key).
const MAX_HEADER_BYTES: usize = 64 * 1024;

/// Bytes of a record around its pixels: tag, render id, index, count,
/// three counts, checksum.
const RECORD_OVERHEAD: usize = 4 + 8 + 4 + 4 + 3 * 8 + 8;

/// Bytes of a record before its pixels.
const RECORD_HEAD: usize = RECORD_OVERHEAD - 8;

/// The header line that ends every header, before its empty line.
const HEAD_CHECKSUM: &str = "head_checksum=";

/// The checkpoint name of an output when `--checkpoint` is not given:
/// `OUTPUT.checkpoint`, beside it.
#[must_use]
pub fn default_path(output: &Path) -> PathBuf {
    let mut name = output.as_os_str().to_owned();
    name.push(".checkpoint");
    PathBuf::from(name)
}

/// The header lines that say which render a checkpoint is of (all but
/// `args`): a resumed render must make the same ones.
pub fn identity(job: &Job<'_>) -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = RenderKey::of(job)
        .fields()
        .iter()
        .map(|(k, v)| (k.to_string(), v.clone()))
        .collect();
    out.push(("window".into(), window_text(job.window)));
    out.push(("samples".into(), samples_text(&job.samples)));
    out.push(("tile".into(), tile_side(job).to_string()));
    out.push(("tiles".into(), job_tiles(job).len().to_string()));
    out
}

/// A checkpoint read back: the render's flags, who it is, and its tiles.
pub struct Saved {
    /// The flags of the render, paths resolved (those kept relative to
    /// the checkpoint's directory are joined to where it is now).
    pub args: RenderArgs,
    /// [`identity`] as written.
    pub identity: Vec<(String, String)>,
    /// The tiles recorded whole.
    pub tiles: Vec<TileFilm>,
    /// Bytes after the last whole record: a record cut off by a kill (or
    /// damaged), dropped; its tile and any after it are rendered again.
    pub dropped_bytes: u64,
    /// Bytes of the header and the whole records: where appending goes on.
    end: u64,
    /// The render's id: the header's checksum, which every record holds.
    id: u64,
}

/// An open checkpoint that finished tiles are appended to.
pub struct Checkpoint {
    path: PathBuf,
    /// The render's id (the header's checksum), written into each record.
    id: u64,
    inner: Mutex<Appender>,
    hook: Option<TestHook>,
    /// Made by this process (not a resumed one).
    new: bool,
}

struct Appender {
    file: File,
    synced: Instant,
    /// Tiles appended by this process.
    appended: u64,
    /// The end of the last whole record. After a failed write the file is
    /// cut back to it and takes no more records, so no whole record ever
    /// follows a torn one.
    end: u64,
    failed: bool,
}

#[derive(Clone, Copy)]
enum TestHook {
    After(u64),
    Writing(u64),
    Hold(u64),
    Stuck(u64),
}

impl Checkpoint {
    /// Writes a new checkpoint's header (atomically) and opens it for
    /// tiles. `args` must hold absolute paths; those below the
    /// checkpoint's directory are written relative to it.
    pub fn create(path: &Path, args: &RenderArgs, job: &Job<'_>) -> Result<Checkpoint> {
        let dir = directory_of(path)?;
        let json =
            serde_json::to_string(&paths_from(args, &dir, anchor)).context("encoding the flags")?;
        let mut head = format!("{MAGIC}\nargs={json}\n");
        for (k, v) in identity(job) {
            head.push_str(&format!("{k}={v}\n"));
        }
        let id = crate::hash::fnv1a(head.as_bytes());
        head.push_str(&format!("{HEAD_CHECKSUM}{id:016x}\n\n"));
        write_atomic(path, |tmp| write_file(tmp, head.as_bytes())).with_context(|| {
            format!(
                "cannot write the checkpoint `{}` (give --checkpoint FILE on a disk with room, or \
                 --no-checkpoint to render without one)",
                path.display()
            )
        })?;
        // A file that cannot be opened for tiles holds none: not left.
        Checkpoint::open_at(path, head.len() as u64, id, true).inspect_err(|_| {
            std::fs::remove_file(path).ok();
        })
    }

    /// Takes the checkpoint [`open`] opened, its records read by
    /// [`Saved::read_tiles`], for more tiles: a torn last record is cut
    /// off.
    pub fn reopen(opened: Opened, saved: &Saved) -> Result<Checkpoint> {
        Checkpoint::take(opened.file, &opened.path, saved.end, saved.id, false)
    }

    fn open_at(path: &Path, end: u64, id: u64, new: bool) -> Result<Checkpoint> {
        let file = open_locked(path)?;
        Checkpoint::take(file, path, end, id, new)
    }

    /// The checkpoint of `file` (open, locked), cut to `end`.
    fn take(mut file: File, path: &Path, end: u64, id: u64, new: bool) -> Result<Checkpoint> {
        let cannot = || format!("cannot open the checkpoint `{}`", path.display());
        file.set_len(end).with_context(cannot)?;
        file.seek(SeekFrom::Start(end)).with_context(cannot)?;
        Ok(Checkpoint {
            path: path.to_path_buf(),
            id,
            inner: Mutex::new(Appender {
                file,
                synced: Instant::now(),
                appended: 0,
                end,
                failed: false,
            }),
            hook: test_hook()?,
            new,
        })
    }

    /// Whether this process made the checkpoint (else it resumes one).
    #[must_use]
    pub fn is_new(&self) -> bool {
        self.new
    }

    /// The file.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Appends a finished tile (one write of the whole record). After a
    /// failed write the file is cut back to its last whole record and
    /// takes no more: the render may go on without it.
    pub fn append(&self, tile: &TileFilm) -> Result<()> {
        let record = encode_record(self.id, tile);
        let mut a = self.inner.lock().unwrap_or_else(|e| e.into_inner());
        match self.hook {
            Some(TestHook::Hold(n)) if a.appended >= n => {
                drop(a);
                while !STOP.load(Ordering::SeqCst) {
                    std::thread::sleep(Duration::from_millis(5));
                }
                a = self.inner.lock().unwrap_or_else(|e| e.into_inner());
            }
            Some(TestHook::Stuck(n)) if a.appended >= n => {
                drop(a);
                loop {
                    std::thread::sleep(Duration::from_millis(50));
                }
            }
            _ => {}
        }
        if a.failed {
            bail!("the checkpoint `{}` failed earlier", self.path.display());
        }
        a.appended += 1;
        if let Some(TestHook::Writing(n)) = self.hook
            && n == a.appended
        {
            a.file.write_all(&record[..record.len() / 2]).ok();
            std::process::abort();
        }
        if let Err(e) = a.file.write_all(&record) {
            // Cut the torn bytes off, and take no more records.
            let end = a.end;
            a.failed = true;
            a.file.set_len(end).ok();
            a.file.seek(SeekFrom::Start(end)).ok();
            return Err(e).with_context(|| {
                format!("cannot append to the checkpoint `{}`", self.path.display())
            });
        }
        a.end += record.len() as u64;
        if let Some(TestHook::After(n)) = self.hook
            && n == a.appended
        {
            std::process::abort();
        }
        if a.synced.elapsed() >= Duration::from_secs(SYNC_SECONDS) {
            a.file.sync_data().ok();
            a.synced = Instant::now();
        }
        Ok(())
    }

    /// Flushes the appended tiles to the disk.
    pub fn sync(&self) -> Result<()> {
        let a = self.inner.lock().unwrap_or_else(|e| e.into_inner());
        a.file
            .sync_data()
            .with_context(|| format!("cannot flush the checkpoint `{}`", self.path.display()))
    }
}

/// `path` opened to read and append, and locked: one process at a time.
/// A second process resuming the same file (a requeued job whose first
/// run still lives) would interleave records; a file system without locks
/// cannot have this check, and goes on.
fn open_locked(path: &Path) -> Result<File> {
    let file = OpenOptions::new()
        .read(true)
        .write(true)
        .open(path)
        .with_context(|| format!("cannot open the checkpoint `{}`", path.display()))?;
    if let Err(std::fs::TryLockError::WouldBlock) = file.try_lock() {
        bail!(
            "the checkpoint `{}` is in use by another strata process",
            path.display()
        );
    }
    Ok(file)
}

/// A checkpoint opened and locked by [`open`], read through this one
/// handle from its header to its last record, then appended to: no other
/// strata process changes it meanwhile.
pub struct Opened {
    file: File,
    path: PathBuf,
}

fn test_hook() -> Result<Option<TestHook>> {
    let Ok(v) = std::env::var(TEST_HOOK_VAR) else {
        return Ok(None);
    };
    let parsed = match v.split_once(':') {
        Some(("after", n)) => n.parse().ok().map(TestHook::After),
        Some(("writing", n)) => n.parse().ok().map(TestHook::Writing),
        Some(("hold", n)) => n.parse().ok().map(TestHook::Hold),
        Some(("stuck", n)) => n.parse().ok().map(TestHook::Stuck),
        _ => None,
    };
    match parsed {
        Some(a) => Ok(Some(a)),
        None => bail!("{TEST_HOOK_VAR}=`{v}`: use after:N, writing:N, hold:N or stuck:N"),
    }
}

fn encode_record(id: u64, tile: &TileFilm) -> Vec<u8> {
    let (index, pixels, stats) = tile;
    let mut out = Vec::with_capacity(RECORD_OVERHEAD + pixels.len() * BYTES_PER_PIXEL);
    out.extend_from_slice(b"TILE");
    out.extend_from_slice(&id.to_le_bytes());
    out.extend_from_slice(&index.to_le_bytes());
    out.extend_from_slice(&(pixels.len() as u32).to_le_bytes());
    for c in [stats.paths, stats.rays, stats.shadow_rays] {
        out.extend_from_slice(&c.to_le_bytes());
    }
    encode_pixels(pixels, &mut out);
    let sum = crate::hash::fnv1a(&out);
    out.extend_from_slice(&sum.to_le_bytes());
    out
}

/// Opens a checkpoint (locked: see [`Opened`]) and reads its header (at
/// most [`MAX_HEADER_BYTES`] of it, checked against its checksum before
/// any of it is used); paths kept relative are joined to the checkpoint's
/// directory. Its tiles are read by [`Saved::read_tiles`], once the job
/// they are of is known. Errors name the file.
pub fn open(path: &Path) -> Result<(Opened, Saved)> {
    let name = || format!("checkpoint `{}`", path.display());
    let file = open_locked(path)?;
    let mut head = Vec::new();
    (&file)
        .take(MAX_HEADER_BYTES as u64 + 2)
        .read_to_end(&mut head)
        .with_context(|| format!("cannot read the checkpoint `{}`", path.display()))?;
    let mut saved = parse_header(&head).with_context(name)?;
    let dir = directory_of(path).with_context(name)?;
    saved.args = paths_from(&saved.args, &dir, resolve);
    let opened = Opened {
        file,
        path: path.to_path_buf(),
    };
    Ok((opened, saved))
}

/// The header of a checkpoint's first bytes: its flags and identity, its
/// render's id, and where its records start.
fn parse_header(bytes: &[u8]) -> Result<Saved> {
    let first = bytes
        .iter()
        .position(|&b| b == b'\n')
        .unwrap_or(bytes.len());
    if &bytes[..first] != MAGIC.as_bytes() {
        if bytes.starts_with(b"strata-checkpoint ") {
            let shown = String::from_utf8_lossy(&bytes[..first.min(40)]).into_owned();
            bail!(
                "a checkpoint of another format (`{shown}`; this build reads `{MAGIC}`): finish \
                 it with the strata that wrote it, or delete it to render again"
            );
        }
        bail!("not a Strata checkpoint (no `{MAGIC}` line)");
    }
    let head_bytes = &bytes[..bytes.len().min(MAX_HEADER_BYTES)];
    let Some(end) = head_bytes.windows(2).position(|w| w == b"\n\n") else {
        bail!("cut off in its header, or a header over 64 KB: not a usable checkpoint");
    };
    // The last header line is the checksum of everything before it; no
    // other byte of the header is used before it matches.
    let last = bytes[..end]
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    let id = std::str::from_utf8(&bytes[last..end])
        .ok()
        .and_then(|l| l.strip_prefix(HEAD_CHECKSUM))
        .and_then(|h| u64::from_str_radix(h, 16).ok())
        .filter(|&id| id == crate::hash::fnv1a(&bytes[..last]));
    let Some(id) = id else {
        bail!("its header is damaged (its checksum does not match): delete it to render again");
    };
    let head = std::str::from_utf8(&bytes[first + 1..last]).context("header is not UTF-8")?;
    let mut args = None;
    let mut identity = Vec::new();
    for line in head.lines() {
        let (k, v) = line.split_once('=').with_context(|| {
            let shown: String = line.chars().take(80).collect();
            format!("header line `{shown}` is not key=value")
        })?;
        match k {
            "args" => {
                args = Some(
                    serde_json::from_str::<RenderArgs>(v)
                        .context("its flags are not those of this build")?,
                );
            }
            _ => identity.push((k.to_string(), v.to_string())),
        }
    }
    let args = args.context("header has no `args`")?;
    Ok(Saved {
        args,
        identity,
        tiles: Vec::new(),
        dropped_bytes: 0,
        end: (end + 2) as u64,
        id,
    })
}

/// The fields of a record before its pixels.
struct RecordHead {
    id: u64,
    index: u32,
    count: u32,
    stats: TileStats,
}

impl RecordHead {
    /// The head at the start of `b` ([`RECORD_HEAD`] bytes), if it starts
    /// with the record tag.
    fn parse(b: &[u8; RECORD_HEAD]) -> Option<RecordHead> {
        let u32_at = |o: usize| u32::from_le_bytes(b[o..o + 4].try_into().unwrap());
        let u64_at = |o: usize| u64::from_le_bytes(b[o..o + 8].try_into().unwrap());
        (&b[..4] == b"TILE").then(|| RecordHead {
            id: u64_at(4),
            index: u32_at(12),
            count: u32_at(16),
            stats: TileStats {
                paths: u64_at(20),
                rays: u64_at(28),
                shadow_rays: u64_at(36),
            },
        })
    }
}

/// One whole record at the start of `b` (its render id and its tile) and
/// its length, or `None` if it is cut off or its checksum fails (a torn
/// append).
#[cfg(test)]
fn parse_record(b: &[u8]) -> Option<((u64, TileFilm), usize)> {
    let head = RecordHead::parse(b.get(..RECORD_HEAD)?.try_into().ok()?)?;
    let body = (head.count as usize).checked_mul(BYTES_PER_PIXEL)?;
    let len = RECORD_OVERHEAD.checked_add(body)?;
    let sum = u64::from_le_bytes(b.get(len - 8..len)?.try_into().ok()?);
    if sum != crate::hash::fnv1a(&b[..len - 8]) {
        return None;
    }
    let pixels = decode_pixels(&b[RECORD_HEAD..RECORD_HEAD + body]);
    Some(((head.id, (head.index, pixels, head.stats)), len))
}

/// Whether the `len` bytes of the record whose first bytes are `head`,
/// read on from `r` a chunk at a time, are there and end in their
/// checksum: a whole record, though not one of this render's shape.
fn whole_record(r: &mut impl Read, head: &[u8], len: u64) -> bool {
    let mut sum = crate::hash::Fnv::default();
    sum.bytes(head);
    let mut left = len - head.len() as u64 - 8;
    let mut buf = vec![0u8; 1 << 16];
    while left > 0 {
        let n = left.min(buf.len() as u64) as usize;
        if r.read_exact(&mut buf[..n]).is_err() {
            return false;
        }
        sum.bytes(&buf[..n]);
        left -= n as u64;
    }
    let mut tail = [0u8; 8];
    r.read_exact(&mut tail).is_ok() && u64::from_le_bytes(tail) == sum.finish()
}

/// The directory a checkpoint is (or will be) in, symbolic links and `..`
/// resolved (it exists: the checkpoint is made in it).
fn directory_of(path: &Path) -> Result<PathBuf> {
    let abs = std::path::absolute(path)
        .with_context(|| format!("cannot resolve `{}`", path.display()))?;
    let dir = abs.parent().unwrap_or(&abs);
    dir.canonicalize()
        .with_context(|| format!("cannot resolve `{}`", dir.display()))
}

/// How a checkpoint in `dir` (resolved) keeps the absolute path `p`:
/// `./REST` if, links and `..` resolved, it lies below `dir` (so a moved
/// job directory takes its files along; the `./` keeps a scene file apart
/// from a built-in scene's name), else as it is.
fn anchor(p: &Path, dir: &Path) -> PathBuf {
    match crate::image_io::real_path(p).strip_prefix(dir) {
        Ok(rest) if !rest.as_os_str().is_empty() => Path::new(".").join(rest),
        _ => p.to_path_buf(),
    }
}

/// A kept path where the checkpoint in `dir` is now: a relative one below
/// `dir`, an absolute one as it is.
fn resolve(p: &Path, dir: &Path) -> PathBuf {
    let rest: PathBuf = p
        .components()
        .filter(|c| *c != std::path::Component::CurDir)
        .collect();
    dir.join(rest)
}

/// `args` with every path (the scene file's, the outputs') mapped by
/// `f(path, dir)`; a built-in scene's name is left alone.
fn paths_from(args: &RenderArgs, dir: &Path, f: impl Fn(&Path, &Path) -> PathBuf) -> RenderArgs {
    let mut out = args.clone();
    let map = |p: &Option<PathBuf>| p.as_deref().map(|p| f(p, dir));
    if crate::scenes::built_in(&args.scene).is_none() {
        out.scene = f(Path::new(&args.scene), dir)
            .to_string_lossy()
            .into_owned();
    }
    out.output = map(&args.output);
    out.stats = map(&args.stats);
    out.spp_map = map(&args.spp_map);
    out.checkpoint = map(&args.checkpoint);
    out
}

impl Saved {
    /// Checks that the job a resumed render makes of the saved flags is
    /// the saved render (else the first field that differs is named).
    pub fn check(&self, job: &Job<'_>) -> Result<()> {
        let now = identity(job);
        for (k, v) in &now {
            match self.identity.iter().find(|(sk, _)| sk == k) {
                Some((_, saved)) if saved == v => {}
                Some((_, saved)) => bail!(
                    "it is of another render than its flags make now: {k} is `{saved}` there, \
                     `{v}` now{}",
                    match k.as_str() {
                        "scene_hash" if crate::scenes::built_in(&job.scene.name).is_some() =>
                            " (this build's built-in scene differs)",
                        "scene_hash" => " (the scene file changed)",
                        "version" => " (another build of strata)",
                        _ => "",
                    }
                ),
                None => bail!("its header has no `{k}`"),
            }
        }
        if self.identity.len() != now.len() {
            bail!("its header has fields this build does not write");
        }
        Ok(())
    }

    /// Reads the records of the checkpoint at `path` (the job [`check`]ed
    /// first): each whole record of this render, up to the first torn
    /// one, whose bytes are dropped. Nothing is read that the job's tiles
    /// could not hold: a record's head must name a tile of the job, once,
    /// with its film's size, before its pixels are read. A whole record
    /// that does not (another render's, or of another shape), and one
    /// whose pixels or counts a `.film` would refuse, is an error.
    ///
    /// [`check`]: Saved::check
    pub fn read_tiles(&mut self, opened: &Opened, job: &Job<'_>) -> Result<()> {
        let cannot = || format!("cannot read the checkpoint `{}`", opened.path.display());
        let len = opened.file.metadata().with_context(cannot)?.len();
        let mut r = std::io::BufReader::new(&opened.file);
        r.seek(SeekFrom::Start(self.end)).with_context(cannot)?;
        let tiles = job_tiles(job);
        let mut seen = vec![false; tiles.len()];
        // The end of the last record read whole (or skipped whole), and
        // the bytes of damaged records skipped before it.
        let (mut at, mut skipped) = (self.end, 0u64);
        loop {
            let mut head = [0u8; RECORD_HEAD];
            if r.read_exact(&mut head).is_err() {
                break;
            }
            let Some(h) = RecordHead::parse(&head) else {
                break;
            };
            let i = h.index as usize;
            let want = tiles.get(i).map(|&t| tile_film_len(job, t)).transpose()?;
            let body = h.count as u64 * BYTES_PER_PIXEL as u64;
            let record = RECORD_OVERHEAD as u64 + body;
            // A record the file does not hold whole: torn (the last).
            if record > len.saturating_sub(at) {
                break;
            }
            let twice = seen.get(i).copied().unwrap_or(false);
            if h.id != self.id || want != Some(h.count as usize) || twice {
                // Damaged, or a whole record that is not one of this
                // render's tiles: only the latter is an error.
                if !whole_record(&mut r, &head, record) {
                    break;
                }
                if h.id != self.id {
                    bail!(
                        "its record of tile {i} belongs to another render (its id is {:016x}, \
                         the header's {:016x}): the file is damaged; delete it to render again",
                        h.id,
                        self.id
                    );
                }
                bail!(
                    "its record of tile {i} ({} pixels) is no tile of this render, or a tile \
                     recorded twice: the file is damaged; delete it to render again",
                    h.count
                );
            }
            let mut rest = vec![0u8; body as usize + 8];
            if r.read_exact(&mut rest).is_err() {
                break;
            }
            at += record;
            let mut sum = crate::hash::Fnv::default();
            sum.bytes(&head);
            sum.bytes(&rest[..body as usize]);
            if sum.finish().to_le_bytes() != rest[body as usize..] {
                // A damaged record of one of the tiles: rendered again;
                // the records after it are kept.
                skipped += record;
                continue;
            }
            seen[i] = true;
            let pixels = decode_pixels(&rest[..body as usize]);
            check_tile(job, tiles[i], &pixels, &h.stats)
                .with_context(|| format!("its record of tile {i} is damaged"))?;
            self.tiles.push((h.index, pixels, h.stats));
        }
        self.dropped_bytes = len.saturating_sub(at) + skipped;
        self.end = at;
        Ok(())
    }
}

/// A tile's record: the sample counts of its film (the tile, and for a
/// splatted filter its margin a side), as a `.film` body's are checked,
/// and its counts of what it traced (a path per sample taken, at most
/// `max_depth` rays and shadow rays a path).
fn check_tile(job: &Job<'_>, tile: Tile, pixels: &[PixelSum], stats: &TileStats) -> Result<()> {
    check_tile_counts(job, tile, pixels)?;
    let layout = job.layout();
    let m = layout.margin();
    let pw = layout.film_size(tile).map_or(0, |s| s.0);
    let taken: u64 = pixels
        .iter()
        .enumerate()
        .filter(|(k, _)| {
            let (x, y) = (*k as u32 % pw, *k as u32 / pw);
            (m..m + tile.width).contains(&x) && (m..m + tile.height).contains(&y)
        })
        .map(|(_, p)| p.taken() as u64)
        .sum();
    let most = taken.saturating_mul(job.max_depth as u64);
    if stats.paths != taken || stats.rays > most || stats.shadow_rays > most {
        bail!(
            "it counts {} paths, {} rays and {} shadow rays for {taken} samples of depth {}",
            stats.paths,
            stats.rays,
            stats.shadow_rays,
            job.max_depth
        );
    }
    Ok(())
}

/// The sample counts of a tile's film: as a `.film` body's are checked.
fn check_tile_counts(job: &Job<'_>, tile: Tile, pixels: &[PixelSum]) -> Result<()> {
    let layout = job.layout();
    let m = layout.margin() as i64;
    let pw = layout.film_size(tile).map_or(0, |s| s.0) as i64;
    for (i, p) in pixels.iter().enumerate() {
        let (dx, dy) = (i as i64 % pw - m, i as i64 / pw - m);
        let owned = (0..tile.width as i64).contains(&dx) && (0..tile.height as i64).contains(&dy);
        if let Some(why) = count_problem(p, owned, &job.samples, job.adaptive) {
            bail!(
                "pixel ({}, {}) {why}",
                tile.x0 as i64 + dx,
                tile.y0 as i64 + dy
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(index: u32, n: usize) -> TileFilm {
        let pixels = (0..n)
            .map(|k| strata::render::PixelSum {
                sum: [k as i64, -1, 7],
                samples: 3,
                ..strata::render::PixelSum::ZERO
            })
            .collect();
        let stats = TileStats {
            paths: 1,
            rays: 2,
            shadow_rays: 3,
        };
        (index, pixels, stats)
    }

    #[test]
    fn records_round_trip_and_torn_ones_are_dropped() {
        let a = encode_record(7, &record(4, 5));
        let b = encode_record(7, &record(9, 2));
        let ((id, got), len) = parse_record(&a).unwrap();
        assert_eq!((id, len), (7, a.len()));
        assert_eq!(got, record(4, 5));
        // Every cut of the second record leaves the first alone readable.
        let both = [a.clone(), b.clone()].concat();
        for cut in 0..b.len() {
            let bytes = &both[..a.len() + cut];
            assert!(parse_record(&bytes[a.len()..]).is_none(), "cut {cut}");
        }
        // A flipped bit anywhere fails the checksum (or the tag/length).
        for at in 0..b.len() {
            let mut bad = b.clone();
            bad[at] ^= 0x10;
            assert!(parse_record(&bad).is_none(), "byte {at}");
        }
    }

    /// A header: its checksum, then records of its id.
    fn file(records: &[Vec<u8>]) -> (Vec<u8>, u64) {
        let head = format!("{MAGIC}\nargs={}\nseed=0\n", args_json());
        let id = crate::hash::fnv1a(head.as_bytes());
        let mut out = format!("{head}{HEAD_CHECKSUM}{id:016x}\n\n").into_bytes();
        for r in records {
            out.extend_from_slice(r);
        }
        (out, id)
    }

    fn args_json() -> String {
        use clap::Parser;
        let cli = crate::cli::Cli::try_parse_from(["strata", "render"]).unwrap();
        let Some(crate::cli::Command::Render(a)) = cli.command else {
            unreachable!()
        };
        serde_json::to_string(&a).unwrap()
    }

    #[test]
    fn a_damaged_header_is_refused_before_use() {
        let (_, id) = file(&[]);
        let (good, _) = file(&[encode_record(id, &record(0, 3))]);
        let saved = parse_header(&good).unwrap();
        assert_eq!(saved.id, id);
        let head_len = good.windows(2).position(|w| w == b"\n\n").unwrap();
        assert_eq!(saved.end, head_len as u64 + 2);
        // Every flipped bit of the header is found before it is used.
        for at in MAGIC.len() + 1..head_len {
            let mut bad = good.clone();
            bad[at] ^= 0x01;
            let e = parse_header(&bad)
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default();
            assert!(e.contains("damaged"), "byte {at}: {e}");
        }
        // The old format is named with this one.
        let e = parse_header(b"strata-checkpoint 1\nargs={}\n\n")
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("strata-checkpoint 1") && e.contains(MAGIC),
            "{e}"
        );
    }

    #[test]
    fn paths_below_the_checkpoint_are_kept_relative() {
        use clap::Parser;
        let root = tempfile::tempdir().unwrap();
        let root = root.path().canonicalize().unwrap();
        let job = root.join("job");
        std::fs::create_dir_all(job.join("out")).unwrap();
        std::fs::write(job.join("s.toml"), "").unwrap();
        // `up/../job` is `job`; `job/../elsewhere` is not below it.
        let up = job.join("out/..");
        let cli = crate::cli::Cli::try_parse_from([
            "strata".into(),
            "render".into(),
            "--scene".into(),
            up.join("s.toml").into_os_string(),
            "-o".into(),
            job.join("out/x.png").into_os_string(),
            "--stats".into(),
            job.join("../s.json").into_os_string(),
        ])
        .unwrap();
        let Some(crate::cli::Command::Render(a)) = cli.command else {
            unreachable!()
        };
        let kept = paths_from(&a, &job, anchor);
        assert_eq!(kept.scene, "./s.toml");
        assert_eq!(kept.output.as_deref(), Some(Path::new("./out/x.png")));
        assert_eq!(kept.stats.as_deref(), Some(job.join("../s.json").as_path()));
        // Moved to /b/job: resolved there, the outside path kept.
        let back = paths_from(&kept, Path::new("/b/job"), resolve);
        assert_eq!(back.scene, "/b/job/s.toml");
        assert_eq!(back.output.as_deref(), Some(Path::new("/b/job/out/x.png")));
        assert_eq!(back.stats, kept.stats);
        // A built-in scene is a name, not a path; a scene file named like
        // one is kept as a path (`./cover`), never read as the built-in.
        let mut b = a.clone();
        b.scene = "cover".into();
        assert_eq!(paths_from(&b, Path::new("/b"), resolve).scene, "cover");
        std::fs::write(job.join("cover"), "").unwrap();
        b.scene = job.join("cover").to_string_lossy().into_owned();
        assert_eq!(paths_from(&b, &job, anchor).scene, "./cover");
    }

    #[test]
    fn one_process_at_a_time_appends() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.checkpoint");
        std::fs::write(&path, b"header\n\n").unwrap();
        let first = Checkpoint::open_at(&path, 8, 0, false).unwrap();
        let e = Checkpoint::open_at(&path, 8, 0, false).err().unwrap();
        assert!(
            e.to_string().contains("in use by another strata process"),
            "{e}"
        );
        drop(first);
        assert!(Checkpoint::open_at(&path, 8, 0, false).is_ok());
    }

    #[test]
    fn default_path_is_beside_the_output() {
        assert_eq!(
            default_path(Path::new("out/x.png")),
            PathBuf::from("out/x.png.checkpoint")
        );
    }
}
