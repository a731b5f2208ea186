//! One way in for every file a scene names (issue 26): `input_file.rs` is where files are
//! opened for reading (regular files only, read no further than their size when opened), so a
//! reader that calls `std::fs` itself would again read `/dev/zero` until memory runs out or
//! block on a FIFO. This test reads the crate's sources and refuses any other way of opening
//! a file for reading, outside the few files that open what the program itself owns.

use opticks_testkit::files::files_with_extension;
use std::path::Path;

#[test]
fn files_are_opened_for_reading_only_through_input_file() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    // Files that open what the program owns, never a path a scene names: /proc's memory
    // figures, the dataset's lock file, the dataset writer's temporary file and folder.
    let own = ["input_file.rs", "memory.rs", "dataset_lock.rs", "dataset_file/writer.rs"];
    let forbidden = ["fs::read(", "fs::read_to_string(", "File::open(", "OpenOptions", "BufReader::new(File"];
    let mut files = Vec::new();
    files_with_extension(&src, "rs", &mut files);
    assert!(files.len() > 30, "found only {} files", files.len());
    let mut found = Vec::new();
    for f in &files {
        let rel = f.strip_prefix(&src).unwrap().to_string_lossy().replace('\\', "/");
        if own.contains(&rel.as_str()) {
            continue;
        }
        let text = std::fs::read_to_string(f).unwrap();
        // Unit tests may read the files they wrote.
        let code = text.split("#[cfg(test)]\nmod tests").next().unwrap();
        for (n, line) in code.lines().enumerate() {
            if !line.trim_start().starts_with("//") && forbidden.iter().any(|p| line.contains(p)) {
                found.push(format!("src/{rel}:{}: {}", n + 1, line.trim()));
            }
        }
    }
    assert!(found.is_empty(), "files opened outside input_file.rs (use opticks_io's input_file): {found:#?}");
}
