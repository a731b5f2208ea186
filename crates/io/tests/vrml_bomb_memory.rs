//! The memory a VRML `USE` bomb costs before it is refused (issue 10 §19: a 2.5 MB bomb reached
//! 4.2 GB before the documented refusal). A counting allocator measures this process's peak
//! heap while the bomb loads; it must stay a small multiple of the input, not grow to the mesh
//! budget the bomb exceeds. One test per binary: the peak is process-wide.

use opticks_io::scene_formats::vrml;
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

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
    // One DEF'd point set of 20,000 points (one triangle), USEd 1,000 times: ~190 KB of text
    // whose copies would need 240 MB, beyond its budget of max(64 MB, 1024 × the text).
    let points: String = (0..20_000).map(|i| format!("{} 0 1,", i % 10)).collect();
    let mut text = format!(
        "#VRML V2.0 utf8\nShape {{ geometry DEF G IndexedFaceSet {{ coord Coordinate {{ point [ {points} ] }} coordIndex [ 0 1 2 -1 ] }} }}\n"
    );
    for i in 0..1000 {
        text.push_str(&format!("Transform {{ translation {i} 0 0 children Shape {{ geometry USE G }} }}\n"));
    }
    let before = NOW.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let e = vrml::load_str(&text, Path::new("bomb.wrl")).map(|_| ()).unwrap_err().to_string();
    assert!(e.contains("bomb.wrl:") && e.contains("multiplies geometry too much"), "{e}");
    let peak = PEAK.load(Ordering::Relaxed) - before;
    // The text, its parse tree and the one distinct mesh: a few times the input (it was the
    // whole budget, over 300 × the input, when the copies were made before counting).
    assert!(peak < 32 * text.len(), "peak heap {peak} bytes for {} bytes of VRML", text.len());
}
