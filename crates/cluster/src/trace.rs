//! Light sampling over the ranks: the master's [`ClusterTracer`], which hands a pass's blocks
//! out on demand and passes the chunks on in block order, and the workers' [`serve`] loop.
//!
//! The conversation (tags in `opticks_io::cluster_wire`): the master sends every worker the [`wire::TraceJob`];
//! a worker loads the scene and answers `READY` (or `FAILED`, which fails the job), then gets
//! `BLOCKS` — as many as it asked for, about two per thread. It asks for the next ones
//! (`REQUEST`) *before* tracing those in parallel, then sends their chunks (`RESULT`): the next
//! blocks are waiting when it is done, and it never idles on the master. An empty `BLOCKS` ends
//! the job for that worker; `QUIT` ends the session (the worker answers `BYE`).
//!
//! Failure: a block is outstanding for at most the worker timeout (`OPTICKS_WORKER_TIMEOUT`
//! seconds, default 60, or ten times the slowest answer seen, whichever is longer); after it
//! the worker counts as lost, its blocks go to the others (or to the master itself when none
//! is left), and a late answer is ignored — the block's samples are the same whoever traces it.
//! Whether the job survives a rank that *died* is the launcher's choice: Open MPI's `mpirun`
//! ends the whole job (the master then gets SIGTERM and saves its partial dataset) unless run
//! with `--enable-recovery` (docs/cluster.md).

use crate::Hooks;
use crate::session::{Served, patient_receive, patient_send, receive_within, world};
use mpi::point_to_point::{Destination, MatchedReceiveVec, Source};
use mpi::topology::Communicator;
use opticks_core::dataset::{Block, Chunk, PassDispatch, PassPlan, TraceSettings};
use opticks_core::scene::Scene;
use opticks_core::trace::trace_block;
use opticks_io::cluster_wire::{self as wire, TraceJob};
use opticks_io::dataset_job::{JobError, JobProgress, PassTracer};
use opticks_io::scene_formats::LoadOptions;
use opticks_io::scene_source::{self, SceneRef, SceneSourceError};
use rayon::prelude::*;
use std::collections::HashMap;
use std::time::{Duration, Instant};

/// Seconds a block may be outstanding before its worker counts as lost (module docs).
fn worker_timeout() -> Duration {
    let secs = std::env::var("OPTICKS_WORKER_TIMEOUT").ok().and_then(|v| v.parse::<f64>().ok());
    Duration::from_secs_f64(secs.filter(|s| s.is_finite() && *s > 0.0).unwrap_or(60.0))
}

/// Blocks a worker asks for at a time: two per thread, so its cores stay busy.
fn blocks_wanted() -> usize {
    2 * rayon::current_num_threads().max(1)
}

/// The master's tracer: the pass's blocks go to the worker ranks; `scene` names the file they
/// load (made absolute, as the workers may start elsewhere), with the `-D` parameters `defines`,
/// the glTF scene `gltf_scene` and the memory limits `limits`.
pub struct ClusterTracer {
    scene: String,
    defines: Vec<(String, String)>,
    gltf_scene: Option<String>,
    limits: opticks_io::scene_formats::LoadLimits,
    hooks: Hooks,
}

impl ClusterTracer {
    /// A tracer whose workers load `scene` (its files, sent as their absolute paths, or a built-in
    /// scene, sent by its label) with the parameters and glTF scene of `options` (a worker
    /// needs no camera).
    pub fn new(scene: &SceneRef, options: &LoadOptions, hooks: Hooks) -> Self {
        // Several files (Radiance's) go one a line, as `SceneRef::label` writes them.
        let absolute: Option<Vec<String>> = (scene.files().into_iter())
            .map(|f| std::fs::canonicalize(f).ok().and_then(|p| p.to_str().map(str::to_owned)))
            .collect();
        let absolute = absolute.filter(|a| !a.is_empty()).map(|a| a.join("\n"));
        ClusterTracer {
            scene: absolute.unwrap_or_else(|| scene.label()),
            defines: options.defines.clone(),
            gltf_scene: options.gltf_scene.clone(),
            limits: options.limits,
            hooks,
        }
    }
}

/// What the master knows of a worker.
#[derive(Clone, Debug, PartialEq)]
enum Worker {
    /// Loading the scene; not asked for anything yet.
    Starting,
    /// Its request for this many blocks is unanswered (it may still be tracing others).
    Idle(usize),
    /// Tracing the blocks it was given, no request pending.
    Busy,
    /// Timed out, or ended for this job: gets nothing more.
    Out,
}

impl PassTracer for ClusterTracer {
    fn trace_pass(
        &self,
        scene: &Scene,
        pass: &PassPlan,
        sink: &mut dyn FnMut(Chunk) -> Result<(), JobError>,
        progress: &dyn JobProgress,
    ) -> Result<Vec<u64>, JobError> {
        let world = world();
        let job = TraceJob {
            scene: self.scene.clone(),
            defines: self.defines.clone(),
            gltf_scene: self.gltf_scene.clone(),
            limits: self.limits,
            fingerprint: scene.fingerprint,
            settings: pass.settings,
        };
        let message = wire::encode_job(&job);
        let ranks: Vec<i32> = (1..world.size()).collect();
        for &r in &ranks {
            world.process_at_rank(r).send_with_tag(&message[..], wire::JOB);
        }
        progress.tracing(pass.lights.iter().map(|p| p.paths).sum());
        let mut workers: HashMap<i32, Worker> = ranks.iter().map(|&r| (r, Worker::Starting)).collect();
        let mut hosts: HashMap<i32, String> = HashMap::new();
        // Each block out carries its worker's rank and when it was sent.
        let mut d = PassDispatch::<(i32, Instant)>::new(pass);
        let (base_timeout, mut slowest) = (worker_timeout(), Duration::ZERO);
        let started = Instant::now();
        let mut done = 0u64;
        let mut stopping = false;
        let mut stats = WireStats::default();
        loop {
            let mut quiet = true;
            while let Some(probed) = world.any_process().immediate_matched_probe() {
                quiet = false;
                let busy = Instant::now();
                let from = probed.1.source_rank();
                let Some((bytes, status)) = receive_within(probed, base_timeout.max(slowest * 10)) else {
                    // Its sender died mid-message: lost, like a worker that sends nothing.
                    workers.insert(from, Worker::Out);
                    (self.hooks.warning)(&format!(
                        "worker rank {from}{}: a message stopped arriving: its blocks go to others",
                        hosts.get(&from).map_or(String::new(), |h| format!(" ({h})"))
                    ));
                    d.reclaim(|t| t.0 == from);
                    continue;
                };
                stats.bytes += bytes.len() as u64;
                stats.messages += 1;
                let rank = status.source_rank();
                let bad = |e: wire::Malformed| JobError::Trace(format!("rank {rank}: {e}"));
                match status.tag() {
                    wire::READY => {
                        let (host, want) = wire::decode_ready(&bytes).map_err(bad)?;
                        hosts.insert(rank, host);
                        workers.insert(rank, Worker::Idle(want.max(1)));
                    }
                    wire::FAILED => {
                        let host = hosts.get(&rank).map_or(String::new(), |h| format!(" ({h})"));
                        let why = String::from_utf8_lossy(&bytes);
                        return Err(JobError::Trace(format!(
                            "worker rank {rank}{host} cannot take part: {why}"
                        )));
                    }
                    wire::REQUEST => {
                        let want = wire::decode_request(&bytes).map_err(bad)?;
                        // A worker that timed out but asks after all gets nothing more.
                        if workers.get(&rank) == Some(&Worker::Busy) {
                            workers.insert(rank, Worker::Idle(want.max(1)));
                        } else {
                            world
                                .process_at_rank(rank)
                                .send_with_tag(&wire::encode_blocks(&[])[..], wire::BLOCKS);
                        }
                    }
                    wire::RESULT => {
                        let oldest = d.tickets().filter(|t| t.0 == rank).map(|t| t.1).min();
                        if let Some(sent) = oldest {
                            slowest = slowest.max(sent.elapsed());
                        }
                        for (seq, chunk) in wire::decode_chunks(&bytes).map_err(bad)? {
                            d.accept(seq, chunk);
                        }
                    }
                    _ => {} // a stray answer of a lost worker
                }
                stats.busy += busy.elapsed();
            }
            let busy = Instant::now();
            // Pass the chunks on in block order.
            while let Some(chunk) = d.next_in_order() {
                done += chunk.paths;
                sink(chunk)?;
                progress.traced(done);
            }
            stats.busy += busy.elapsed();
            if !stopping && progress.stop() {
                stopping = true;
                d.stop();
            }
            // Lost workers: their blocks go to the others.
            let timeout = base_timeout.max(slowest * 10);
            let mut lost: Vec<i32> = d.tickets().filter(|t| t.1.elapsed() > timeout).map(|t| t.0).collect();
            lost.dedup();
            for r in lost {
                if workers.insert(r, Worker::Out) != Some(Worker::Out) {
                    let host = hosts.get(&r).map_or(String::new(), |h| format!(" ({h})"));
                    (self.hooks.warning)(&format!(
                        "worker rank {r}{host} sent nothing for {:.0} s: its blocks go to others",
                        timeout.as_secs_f64()
                    ));
                }
                d.reclaim(|t| t.0 == r);
            }
            // Hand out blocks to the workers waiting for them.
            for (&r, w) in workers.iter_mut() {
                let Worker::Idle(want) = *w else { continue };
                let now = Instant::now();
                let blocks = d.hand_out(want, || (r, now));
                if blocks.is_empty() && !stopping && d.outstanding() {
                    continue; // nothing now, but a lost worker's blocks may come back
                }
                world.process_at_rank(r).send_with_tag(&wire::encode_blocks(&blocks)[..], wire::BLOCKS);
                *w = if blocks.is_empty() { Worker::Out } else { Worker::Busy };
            }
            if d.is_over() {
                break; // (chunks past a gap, of blocks lost while stopping, are dropped)
            }
            // No worker left (all lost, or none ever answered): the master traces the rest.
            if started.elapsed() > base_timeout {
                // Not started within the timeout: counted out (a late `READY` still counts it in).
                workers.values_mut().filter(|w| **w == Worker::Starting).for_each(|w| *w = Worker::Out);
            }
            if workers.values().all(|w| *w == Worker::Out) {
                let blocks = d.hand_out(blocks_wanted(), || (0, Instant::now()));
                let chunks: Vec<(u64, Chunk)> =
                    blocks.par_iter().map(|(seq, b)| (*seq, trace(scene, &pass.settings, b))).collect();
                for (seq, c) in chunks {
                    d.accept(seq, c);
                }
                continue;
            }
            if quiet {
                std::thread::sleep(Duration::from_micros(200));
            }
        }
        // Workers still waiting are told the job is over.
        for (&r, w) in workers.iter_mut() {
            if matches!(w, Worker::Idle(_)) {
                world.process_at_rank(r).send_with_tag(&wire::encode_blocks(&[])[..], wire::BLOCKS);
                *w = Worker::Out;
            }
        }
        progress.traced_all();
        stats.report(done, started.elapsed(), ranks.len(), &self.hooks);
        Ok(d.traced().to_vec())
    }
}

/// What the master received, and how long it spent on it (receiving, decoding, passing chunks
/// to the writer, which blocks when the disk falls behind): the measure of its bound.
#[derive(Default)]
struct WireStats {
    bytes: u64,
    messages: u64,
    busy: Duration,
}

impl WireStats {
    /// One note on stderr (docs/cluster.md explains how to read it).
    fn report(&self, paths: u64, elapsed: Duration, workers: usize, hooks: &Hooks) {
        let per_path = self.bytes as f64 / paths.max(1) as f64;
        let rate = self.bytes as f64 / self.busy.as_secs_f64().max(1e-9) / 1e6;
        (hooks.note)(&format!(
            "cluster: {workers} workers, {paths} paths in {:.2} s; {:.1} MB received in {} messages ({per_path:.1} \
             bytes/path); master busy {:.2} s ({:.0}%, {rate:.0} MB/s while busy)",
            elapsed.as_secs_f64(),
            self.bytes as f64 / 1e6,
            self.messages,
            self.busy.as_secs_f64(),
            100.0 * self.busy.as_secs_f64() / elapsed.as_secs_f64().max(1e-9),
        ));
    }
}

/// One block of a pass of `settings`, as every rank traces it.
fn trace(scene: &Scene, settings: &TraceSettings, b: &Block) -> Chunk {
    trace_block(scene, settings, b.light.scene_light, b.light.table_index, b.index, b.paths)
}

/// What a worker's loaded scene was loaded from: the file, its `-D` parameters, its glTF scene,
/// the memory limits it was loaded within.
type SceneKey = (String, Vec<(String, String)>, Option<String>, opticks_io::scene_formats::LoadLimits);

/// A worker's life: jobs until `QUIT` ([`Served::Done`], also when a job this worker could not
/// do was reported to the master, whose verb fails with the reason).
pub(crate) fn serve(threads: usize, hooks: &Hooks) -> Served {
    if threads > 0 {
        let _ = rayon::ThreadPoolBuilder::new().num_threads(threads).build_global();
    }
    let world = world();
    let master = world.process_at_rank(0);
    let host = mpi::environment::processor_name().unwrap_or_default();
    // A signal (a scheduler's SIGTERM reaches every rank) does not end a worker: the master
    // decides when the job ends, and the blocks in hand are finished and sent (the front end
    // keeps signals from ending the process meanwhile). Only a master that then stays silent
    // for the worker timeout is given up on.
    let signalled = std::sync::OnceLock::new();
    let give_up =
        || (hooks.stop_requested)() && signalled.get_or_init(Instant::now).elapsed() > worker_timeout();
    let mut loaded: Option<(SceneKey, Scene)> = None;
    loop {
        let Some((bytes, status)) = patient_receive::<u8>(&master, None, &give_up) else {
            return Served::GaveUp;
        };
        match status.tag() {
            wire::QUIT => {
                master.send_with_tag(&[0u8][..], wire::BYE);
                return Served::Done;
            }
            wire::JOB => {}
            _ => continue, // the end of a job this worker had already left
        }
        let job = match wire::decode_job(&bytes) {
            Ok(job) => job,
            Err(e) => {
                master.send_with_tag(e.to_string().as_bytes(), wire::FAILED);
                continue;
            }
        };
        let wanted = (job.scene.clone(), job.defines.clone(), job.gltf_scene.clone(), job.limits);
        if loaded.as_ref().is_none_or(|(spec, _)| *spec != wanted) {
            loaded = match load_scene(&job) {
                Ok(scene) => Some((wanted, scene)),
                Err(e) => {
                    master.send_with_tag(error_chain(&e).as_bytes(), wire::FAILED);
                    None
                }
            };
        }
        let Some((_, scene)) = &loaded else { continue };
        if scene.fingerprint != job.fingerprint {
            let why = format!(
                "its {} has geometry/material fingerprint {}, the master's {}",
                job.scene,
                scene.fingerprint.geometry_hex(),
                job.fingerprint.geometry_hex()
            );
            master.send_with_tag(why.as_bytes(), wire::FAILED);
            continue;
        }
        master.send_with_tag(&wire::encode_ready(&host, blocks_wanted())[..], wire::READY);
        loop {
            let Some((bytes, status)) = patient_receive::<u8>(&master, None, &give_up) else {
                return Served::GaveUp;
            };
            if status.tag() == wire::QUIT {
                master.send_with_tag(&[0u8][..], wire::BYE);
                return Served::Done;
            }
            let blocks = match wire::decode_blocks(&bytes) {
                Ok(blocks) => blocks,
                Err(e) => {
                    // Fails the job at once (the master waits for nothing) and waits for `QUIT`.
                    master.send_with_tag(format!("{e} from the master").as_bytes(), wire::FAILED);
                    break;
                }
            };
            if blocks.is_empty() {
                break; // the job is over for this worker
            }
            master.send_with_tag(&wire::encode_request(blocks_wanted())[..], wire::REQUEST);
            let chunks: Vec<(u64, Chunk)> =
                blocks.par_iter().map(|(seq, b)| (*seq, trace(scene, &job.settings, b))).collect();
            patient_send(&master, &wire::encode_chunks(&chunks), wire::RESULT);
        }
    }
}

/// Loads the scene of a job as the master loaded it (its warnings are the master's to print).
fn load_scene(job: &TraceJob) -> Result<Scene, SceneSourceError> {
    let scene = SceneRef::parse(&job.scene)?;
    let options = LoadOptions {
        defines: job.defines.clone(),
        camera: None,
        gltf_scene: job.gltf_scene.clone(),
        limits: job.limits,
    };
    let loaded = scene_source::load(&scene, &options)?;
    Ok(scene_source::build(&scene, &loaded.description)?.scene)
}

/// An error and its causes joined by ": ", leaving out a cause the message before it already
/// ends with (what the worker sends the master, which reports it).
fn error_chain(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        let part = c.to_string();
        if !text.ends_with(&part) {
            text.push_str(": ");
            text.push_str(&part);
        }
        cause = c.source();
    }
    text
}

/// The master's end of the session: every worker is told to quit, and their answers awaited
/// (messages a lost worker still sends are received and dropped, so none blocks on a send).
/// Workers that do not answer within the worker timeout are reported; returns whether all
/// answered (MPI's final handshake would wait forever for a dead one).
pub(crate) fn release_workers(hooks: &Hooks) -> bool {
    let world = world();
    let mut waiting: Vec<i32> = (1..world.size()).collect();
    for &r in &waiting {
        world.process_at_rank(r).send_with_tag(&[0u8][..], wire::QUIT);
    }
    let deadline = Instant::now() + worker_timeout();
    while !waiting.is_empty() && Instant::now() < deadline {
        match world.any_process().immediate_matched_probe() {
            Some(probed) => {
                let (_, status) = probed.matched_receive_vec::<u8>();
                if status.tag() == wire::BYE {
                    waiting.retain(|&r| r != status.source_rank());
                }
            }
            None => std::thread::sleep(Duration::from_millis(1)),
        }
    }
    if !waiting.is_empty() {
        (hooks.warning)(&format!("worker ranks {waiting:?} did not answer at the end (lost?)"));
    }
    waiting.is_empty()
}
