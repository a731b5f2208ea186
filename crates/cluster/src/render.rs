//! `render` over the ranks: every rank runs the verb (opening the dataset is read-only), the
//! core's fixed runs of chunks (`opticks_core::sensor::render_runs`) are split over the
//! workers — run r to worker 1 + r mod (N − 1) — and each worker sends its run films, in order,
//! to the master, which adds them in run order ([`opticks_core::sensor::RunFold`]). The image is
//! therefore bit for bit the single-process one. The master only adds: with N ranks, N − 1
//! render. Images too large for run films (`opticks_core::film::private_films`) are split the
//! same way but each worker sends one film of all its runs, accumulated like the single-process
//! render of such sizes (one shared film): equal to it within float rounding.

use crate::ClusterError;
use crate::session::{patient_receive, patient_send, world};
use mpi::topology::Communicator;
use opticks_core::film::{Film, private_films};
use opticks_core::scene::Scene;
use opticks_core::sensor::{AsBatch, RunFold, Sensor, render_runs, run_count};
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
/// worker (its part went to the master). `progress(done, total)` counts the films the master
/// has added; `stop_requested` ends the master's wait for them (the job then ends:
/// [`crate::Session::finish`]). A batch's error `E` ends the render; the cluster's own errors
/// become one (`E: From<ClusterError>`).
pub fn render<B: AsBatch, E: Send + From<ClusterError>>(
    scene: &Scene,
    camera: &Sensor,
    count: usize,
    batch: impl Fn(usize) -> Result<B, E> + Sync,
    progress: impl Fn(usize, usize),
    stop_requested: fn() -> bool,
) -> Result<Option<Film>, E> {
    let world = world();
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let (width, height) = (camera.width(), camera.height());
    let runs = run_count(count, width, height);
    // Images too large for run films: each worker renders the batches of its runs into one
    // shared film, and the master adds the workers' films in rank order (equal to the
    // single-process render within float rounding, as that render is for such sizes).
    let in_runs = private_films(width, height);
    let films = if in_runs { runs } else { (size - 1).min(runs) };
    if rank == 0 {
        let mut fold = RunFold::new(width, height);
        for r in 0..films {
            // Each worker sends its films in order, and messages between two ranks do not
            // overtake one another: the next message from the owner is film r.
            let from = world.process_at_rank(owner(r, size) as i32);
            let Some((pixels, _)) = patient_receive::<f64>(&from, Some(wire::FILM), &stop_requested) else {
                return Err(ClusterError::Interrupted.into());
            };
            if pixels.len() != film_len(width, height) {
                let rank = owner(r, size);
                return Err(ClusterError::BadFilm { rank, values: pixels.len(), width, height }.into());
            }
            let mut film = Film::new(width, height);
            for (p, v) in film.pixels.iter_mut().zip(pixels.chunks_exact(3)) {
                *p = [v[0], v[1], v[2]];
            }
            fold.add(r, &film);
            progress(r + 1, films);
        }
        return Ok(Some(fold.into_film()));
    }
    let mine: Vec<usize> = (0..runs).filter(|&r| owner(r, size) == rank).collect();
    let master = world.process_at_rank(0);
    let send = |film: &Film| {
        let flat: Vec<f64> = film.pixels.iter().flatten().copied().collect();
        patient_send(&master, &flat, wire::FILM);
    };
    if in_runs {
        render_runs(
            scene,
            camera,
            count,
            &mine,
            batch,
            |_| {},
            |_, film| {
                send(&film);
                Ok(())
            },
        )?;
    } else if !mine.is_empty() {
        // The batches of this rank's runs, in order.
        let per_run = opticks_core::sensor::batches_per_run(width, height);
        let batches: Vec<usize> =
            mine.iter().flat_map(|&r| (r * per_run)..((r + 1) * per_run).min(count)).collect();
        send(&opticks_core::sensor::render(scene, camera, batches.len(), |i| batch(batches[i]), |_| {})?);
    }
    Ok(None)
}
