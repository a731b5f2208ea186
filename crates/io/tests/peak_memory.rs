//! Peak heap of readers whose memory must stay within a documented bound of their input: a
//! VRML `USE` bomb before it is refused (issue 10 §19: a 2.5 MB bomb reached 4.2 GB before the
//! documented refusal) and a texture image as it is decoded (issue 26: a 65 KB 8192² PNG took
//! 1.58 GB). A counting allocator measures this process's peak heap; the count is process-wide,
//! so each test holds [`ONE_AT_A_TIME`] from its first allocation to its last (another test's
//! setup would otherwise count in its peak). A binary of its own: a global allocator.

use opticks_io::scene_formats::vrml;
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Held by each test while it measures.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

/// Taken by each test before anything else, held to its end.
fn my_turn() -> std::sync::MutexGuard<'static, ()> {
    ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner())
}

/// The peak heap, above what was in use when it started, while `f` runs.
fn peak_of<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let before = NOW.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let value = f();
    (value, PEAK.load(Ordering::Relaxed).saturating_sub(before))
}

struct Counting;
static NOW: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is forwarded to the system allocator unchanged; only sizes are counted.
// A global allocator can only be written as an `unsafe impl`, hence the allowance on this item.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let now = NOW.fetch_add(l.size(), Ordering::Relaxed) + l.size();
        PEAK.fetch_max(now, Ordering::Relaxed);
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        NOW.fetch_sub(l.size(), Ordering::Relaxed);
        unsafe { System.dealloc(p, l) }
    }
}

#[global_allocator]
static A: Counting = Counting;

#[test]
fn a_use_bomb_is_refused_before_memory_grows_past_a_small_multiple_of_the_input() {
    let _turn = my_turn();
    // One DEF'd point set of 20,000 points (one triangle), USEd 1,000 times: ~190 KB of text
    // whose copies would need 240 MB, beyond its budget of max(64 MB, 1024 × the text).
    let points: String = (0..20_000).map(|i| format!("{} 0 1,", i % 10)).collect();
    let mut text = format!(
        "#VRML V2.0 utf8\nShape {{ geometry DEF G IndexedFaceSet {{ coord Coordinate {{ point [ {points} ] }} coordIndex [ 0 1 2 -1 ] }} }}\n"
    );
    for i in 0..1000 {
        text.push_str(&format!("Transform {{ translation {i} 0 0 children Shape {{ geometry USE G }} }}\n"));
    }
    let (e, peak) =
        peak_of(|| vrml::load_str(&text, Path::new("bomb.wrl")).map(|_| ()).unwrap_err().to_string());
    assert!(e.contains("bomb.wrl:") && e.contains("multiplies geometry too much"), "{e}");
    // The text, its parse tree and the one distinct mesh: a few times the input (it was the
    // whole budget, over 300 × the input, when the copies were made before counting).
    assert!(peak < 32 * text.len(), "peak heap {peak} bytes for {} bytes of VRML", text.len());
}

/// An 8-bit texture is read at its 12-byte linear texels plus its decoded image and the
/// decoder's buffers, within 20 bytes a texel (`texture_file::MAX_TEXELS`): a full-size f32
/// copy beside the texels, as before, takes 27.
#[test]
fn an_8_bit_texture_is_read_within_20_bytes_a_texel() {
    let _turn = my_turn();
    let (w, h) = (2048u32, 2048u32);
    let image = image::RgbImage::from_pixel(w, h, image::Rgb([200, 100, 50]));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("flat.png");
    image.save(&path).unwrap();
    drop(image);
    let (texture, peak) = peak_of(|| opticks_io::texture_file::read_texture(&path, false).unwrap());
    assert_eq!(texture.texels.len(), (w * h) as usize);
    let texels = (w * h) as usize;
    assert!(peak < 20 * texels, "peak heap {peak} bytes, {:.1} a texel", peak as f64 / texels as f64);
}
