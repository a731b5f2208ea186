//! `render` over the ranks: every rank runs the verb (opening the dataset is read-only), the
//! core's fixed runs of chunks (`opticks_core::sensor::render_runs`) are split over the
//! workers — run r to worker 1 + r mod (N − 1) — and each worker sends its run films, in order,
//! to the master, which adds them in run order ([`opticks_core::sensor::RunFold`]). The image is
//! therefore bit for bit the single-process one. The master only adds: with N ranks, N − 1
//! render.

use super::{patient_receive, patient_send, world};
use mpi::topology::Communicator;
use opticks_core::film::Film;
use opticks_core::scene::Scene;
use opticks_core::sensor::{RunFold, SampleBatch, Sensor, render_runs, run_count, splat};
use opticks_io::cluster_wire as wire;

/// f64 values in a `width`×`height` film.
fn film_len(width: u32, height: u32) -> usize {
    3 * width as usize * height as usize
}

/// The rank that renders run `run` of a job of `size` ranks.
fn owner(run: usize, size: usize) -> usize {
    1 + run % (size - 1)
}

/// Renders `count` batches through `camera` on the cluster: the film on the master, `None` on a
/// worker (its part went to the master). `progress(done, total)` counts runs on the master.
pub fn render<'a>(
    scene: &Scene,
    camera: &Sensor,
    count: usize,
    batch: impl Fn(usize) -> anyhow::Result<SampleBatch<'a>> + Sync,
    progress: impl Fn(usize, usize),
) -> anyhow::Result<Option<Film>> {
    let world = world();
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let (width, height) = (camera.width(), camera.height());
    let runs = run_count(count, width, height);
    if rank == 0 {
        let mut fold = RunFold::new(width, height);
        for r in 0..runs {
            // Each worker sends its runs in order, and messages between two ranks do not
            // overtake one another: the next message from the owner is run r's film.
            let from = world.process_at_rank(owner(r, size) as i32);
            let (pixels, _) = patient_receive::<f64>(&from, Some(wire::FILM));
            if pixels.len() != film_len(width, height) {
                anyhow::bail!(
                    "rank {} sent a film of {} values for {width}x{height}",
                    owner(r, size),
                    pixels.len()
                );
            }
            let mut film = Film::new(width, height);
            for (p, v) in film.pixels.iter_mut().zip(pixels.chunks_exact(3)) {
                *p = [v[0], v[1], v[2]];
            }
            fold.add(r, &film);
            progress(r + 1, runs);
        }
        return Ok(Some(fold.into_film()));
    }
    let mine: Vec<usize> = (0..runs).filter(|&r| owner(r, size) == rank).collect();
    let master = world.process_at_rank(0);
    render_runs(
        (width, height),
        count,
        &mine,
        batch,
        |_| {},
        |b, film| splat(scene, camera, b, film),
        |_, film| {
            let flat: Vec<f64> = film.pixels.iter().flatten().copied().collect();
            patient_send(&master, &flat, wire::FILM);
            Ok(())
        },
    )?;
    Ok(None)
}
