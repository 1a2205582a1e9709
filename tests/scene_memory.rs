//! Issue 38, "Scenes are owned, not leaked": a scene file loaded, built and dropped
//! keeps nothing once nothing uses it. A lesson of edits, or a large file reloaded all
//! afternoon, must not grow the lab's memory.
//!
//! This binary counts every byte it allocates (a `#[global_allocator]` that forwards to
//! the system allocator and keeps the number of bytes live), so a scene file of a
//! megabyte kept by each load would show as a gigabyte after a thousand loads. Each
//! test loads 10 times first (whatever is made once, on first use, is made then), reads
//! the bytes live, loads 990 times more and reads them again.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use particle_lab::physics::Integrator;
use particle_lab::scenes::{self, SceneEntry, file};
use particle_lab::ui::compare::Change;
use particle_lab::ui::lab::Lab;

/// The system allocator, counting the bytes live in [`LIVE`].
struct Counting;

/// Bytes allocated and not yet freed, by every thread of this binary.
static LIVE: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is passed to the system allocator unchanged; the counter only
// records the sizes that succeeded.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's guarantees for `layout` are the system allocator's.
        let block = unsafe { System.alloc(layout) };
        if !block.is_null() {
            LIVE.fetch_add(layout.size(), Ordering::Relaxed);
        }
        block
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as for `alloc`.
        let block = unsafe { System.alloc_zeroed(layout) };
        if !block.is_null() {
            LIVE.fetch_add(layout.size(), Ordering::Relaxed);
        }
        block
    }

    unsafe fn dealloc(&self, block: *mut u8, layout: Layout) {
        // SAFETY: `block` came from this allocator, that is from the system's, with `layout`.
        unsafe { System.dealloc(block, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, block: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: as for `dealloc`, and `new_size` is the caller's to vouch for.
        let moved = unsafe { System.realloc(block, layout, new_size) };
        if !moved.is_null() {
            LIVE.fetch_add(new_size, Ordering::Relaxed);
            LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        }
        moved
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Most bytes a thousand loads may add to what ten left live: a few bytes of a cache
/// growing now and then, never a copy of the file (a megabyte) or of its tables.
const FLAT: isize = 256 << 10;

/// Loads run first, so that whatever is made once (on first use) is made.
const WARM_UP: usize = 10;

/// Loads in all.
const LOADS: usize = 1_000;

/// The tests share the one counter: they run one at a time.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

/// Bytes live in this process now.
fn live() -> isize {
    LIVE.load(Ordering::Relaxed) as isize
}

/// A scene file of about a megabyte: a 20 x 20 cloth of rods, 200 named particles
/// (labels), and comment lines. `version` (0 to 999) sets the default of its one
/// parameter, `mass`, so that each version is another text of the same length.
fn heavy_file(version: usize) -> String {
    let mut text = format!(
        "[scene]\nname = \"heavy\"\nsummary = \"A cloth and a crowd, padded to a megabyte\"\n\n\
         [[param]]\nname = \"mass\"\nunit = \"kg\"\ndefault = 1.{version:03}\nmin = 0.1\nmax = 10\n\
         help = \"Mass of the cloth\"\n\n\
         [[grid]]\nname = \"cloth\"\nrows = 20\ncols = 20\norigin = [0, 3, 0]\n\
         step_col = [0.1, 0, 0]\nstep_row = [0, 0, 0.1]\nmass = \"mass / 400\"\npin = [[0, 0], [0, -1]]\n\
         link = \"rod\"\n\n"
    );
    for k in 0..200 {
        text.push_str(&format!("[[particle]]\nname = \"p{k}\"\nposition = [{k}, 1, -2]\n\n"));
    }
    let comment = format!("# {}\n", "padding ".repeat(12));
    while text.len() < 1 << 20 {
        text.push_str(&comment);
    }
    text
}

/// Bytes live after the last of [`LOADS`] calls of `load` less those after the
/// [`WARM_UP`]th; `load` is given the call's number.
fn growth(mut load: impl FnMut(usize)) -> isize {
    for n in 0..WARM_UP {
        load(n);
    }
    let before = live();
    for n in WARM_UP..LOADS {
        load(n);
    }
    let grown = live() - before;
    eprintln!("{LOADS} loads: {grown} bytes more live than after {WARM_UP}");
    grown
}

/// Loads `text`, builds its scene with the defaults and a changed parameter, and drops both.
fn load_build_drop(text: &str) {
    let entry = file::load_text(text, "heavy.toml", None).expect("the file loads");
    let mut scene = scenes::build_entry(&entry, &[]).expect("the file builds");
    scene.set_param("mass", 2.0).expect("mass takes 2 kg");
    assert_eq!(scene.world().particles.len(), 600);
}

#[test]
fn loading_the_same_file_a_thousand_times_keeps_memory_flat() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let text = heavy_file(0);
    let grown = growth(|_| load_build_drop(&text));
    assert!(grown < FLAT, "{LOADS} loads of the same file kept {grown} bytes (at most {FLAT})");
}

#[test]
fn loading_a_thousand_different_files_keeps_memory_flat() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let grown = growth(|n| load_build_drop(&heavy_file(n)));
    assert!(grown < FLAT, "{LOADS} loads of different files kept {grown} bytes (at most {FLAT})");
}

/// The window's doors: File → Open of a file's text, and loading a snapshot that
/// carries its scene file, one after the other on one lab.
#[test]
fn opening_files_and_snapshots_in_the_lab_a_thousand_times_keeps_memory_flat() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let mut lab = Lab::new("pendulum", &[]).expect("the pendulum is registered");
    let grown = growth(|n| {
        let text = heavy_file(n);
        assert!(lab.open_scene_text("heavy.toml", &text), "{}", lab.status);
        lab.run_steps(1);
        let snapshot = lab.snapshot().expect("the scene saves");
        lab.load_snapshot(&snapshot).expect("the snapshot loads");
        assert_eq!(lab.scene.source().map(|(source, _)| source == text), Some(true));
    });
    assert!(grown < FLAT, "{LOADS} opens in the lab kept {grown} bytes (at most {FLAT})");
}

/// The window's hot reload: once an edit of the open file has been read, the load it
/// replaces is freed, though the lab, its scene and a Compare copy all held it.
#[test]
fn a_hot_reload_frees_the_load_it_replaces() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let dir = std::env::temp_dir().join(format!("particle-lab-scene-memory-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("heavy.toml");
    std::fs::write(&path, heavy_file(0)).unwrap();
    let mut lab = Lab::new("pendulum", &[]).expect("the pendulum is registered");
    assert!(lab.open_scene_file(&path), "{}", lab.status);
    lab.set_param("mass", 2.0);
    lab.start_compare(Change::Integrator(Integrator::Rk4));
    assert!(lab.compare.is_some(), "{}", lab.status);
    let SceneEntry::File(before) = &lab.entry else { panic!("the lab is on a scene file") };
    let before = Arc::downgrade(before);

    // The watch starts now: an edit made at once could come before it.
    std::thread::sleep(Duration::from_millis(100));
    let edited = heavy_file(1);
    std::fs::write(&path, &edited).unwrap();
    let start = Instant::now();
    while lab.scene.source().map(|(text, _)| text) != Some(edited.as_str()) {
        assert!(start.elapsed() < Duration::from_secs(10), "the edit was not reloaded: {}", lab.status);
        lab.poll_scene_file();
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(lab.scene.params().get("mass"), 2.0, "the reload keeps the value moved");
    assert_eq!(before.strong_count(), 0, "the load before the edit is still held");
    drop(lab);
    let _ = std::fs::remove_dir_all(&dir);
}
