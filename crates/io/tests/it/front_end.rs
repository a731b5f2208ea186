//! The libraries are a front end's whole API (issue 24): a second front end — the Python
//! package, a server — traces, inspects, renders, relights and measures a dataset with
//! `opticks-core` and `opticks-io` alone, as this test does, without a line of the CLI's code.

use opticks_core::dataset::{LightScale, TraceSettings, new_trace};
use opticks_core::math::Rgb;
use opticks_core::sensor::{Sensor, render};
use opticks_io::dataset_info::DatasetInfo;
use opticks_io::dataset_job::{NewPaths, write_dataset};
use opticks_io::measurement::{Estimator, Measured, Place, Request};
use opticks_io::opened::OpenedDataset;
use opticks_io::scene_formats::LoadOptions;
use opticks_io::scene_ref::label_for;
use opticks_io::scene_source::{self, SceneRef};

#[test]
fn a_second_front_end_needs_only_the_libraries() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("c.opds");

    // Trace: load and build the scene, plan the pass, write the dataset.
    let scene_ref = SceneRef::cornell();
    let loaded = scene_source::load(&scene_ref, &LoadOptions::default()).unwrap();
    let scene = scene_source::build(&scene_ref, &loaded.description).unwrap().scene;
    let settings = TraceSettings { paths: 40_000, seed: 3, ..Default::default() };
    let (header, pass) = new_trace(&scene, &label_for(&scene_ref.label(), &output), settings);
    let report = write_dataset(&output, header, &[], Some(NewPaths { scene: &scene, pass }), &()).unwrap();
    assert_eq!(report.table.total_paths(), 40_000);

    // Inspect: what `opticks info` prints, as a value.
    let info = DatasetInfo::read(&output).unwrap();
    assert_eq!((info.paths, info.samples), (40_000, report.summary.samples));
    assert!(info.bidirectional && info.lines().iter().any(|l| l.starts_with("paths     40000")));
    let json = serde_json::to_value(&info).unwrap();
    assert_eq!(json["scene"]["builtin"], "builtin:cornell", "{json}");

    // Render through the scene's camera, then relit: the light at twice its power doubles
    // every pixel exactly (relighting never re-traces).
    let render_with = |scales: &[LightScale]| {
        let data = OpenedDataset::open(&output, None, &LoadOptions::default()).unwrap().lit(scales).unwrap();
        let camera = Sensor::new(&data.description().camera.unwrap()).unwrap();
        let film = render(data.scene(), &camera, data.count(), |i| data.batch(i), |_| {}).unwrap();
        (data, film)
    };
    let (data, film) = render_with(&[]);
    let (_, twice) = render_with(&[LightScale { light: "light".into(), factor: Rgb::splat(2.0) }]);
    assert!(!film.is_black());
    for (a, b) in film.pixels.iter().zip(&twice.pixels) {
        assert_eq!([2.0 * a[0], 2.0 * a[1], 2.0 * a[2]], *b);
    }

    // Measure the red wall: a typed request, its reading, its CSV and summary.
    let request = Request {
        places: vec![Place::Surface("red".into())],
        cells: Some((2, 2)),
        estimator: None,
        connections: None,
        direct_samples: None,
        seed: None,
        heatmap: false,
        daylight_factor: false,
    };
    assert_eq!(request.check().unwrap(), Estimator::Samples, "a mesh's default");
    let (layout, warning) = request.layout(0, &data).unwrap();
    assert!(warning.is_none());
    let reading = data.measure(&layout, request.settings().unwrap(), |_| {}, || false).unwrap();
    let measured = Measured {
        layout: &layout,
        reading: &reading,
        estimator: Estimator::Samples,
        daylight: None,
        photometry: data.scene().photometry,
    };
    assert!(!measured.is_black());
    assert_eq!(measured.csv().lines().count(), 1 + 4, "a header and four cells");
    assert!(
        measured.summary("m.csv")[0].starts_with("2x2 cells on 4.0000 m²"),
        "{:?}",
        measured.summary("m.csv")
    );

    // A request that means nothing is refused before any work.
    let points = Request { places: vec![Place::Points(Vec::new())], cells: Some((2, 2)), ..request };
    assert!(points.check().unwrap_err().to_string().contains("--cells is for planes"));
}
