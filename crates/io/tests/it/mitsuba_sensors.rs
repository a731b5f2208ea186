//! The Mitsuba 3 XML loader's sensors and films: `fov_axis` conversions, the camera frames of
//! `perspective`, `thinlens` and `orthographic` against Mitsuba's, the default focal length, and
//! the film's crop window and reconstruction filter.

use crate::mitsuba::{assert_close, err, scene};
use opticks_core::math::Vec3;
use opticks_core::scene::CameraKind;
use opticks_io::scene_formats::mitsuba::fov_to_x;

#[test]
fn fov_axis_conversions() {
    let tan = |deg: f64| (deg.to_radians() / 2.0).tan();
    let atan2x = |t: f64| 2.0 * t.atan().to_degrees();
    // 200×100: aspect 2.
    assert_eq!(fov_to_x(60.0, "x", 200, 100), Some(60.0));
    let y = fov_to_x(60.0, "y", 200, 100).unwrap();
    assert!((y - atan2x(2.0 * tan(60.0))).abs() < 1e-9 && (y - 98.2132).abs() < 1e-3);
    assert_eq!(fov_to_x(60.0, "smaller", 200, 100), Some(y));
    assert_eq!(fov_to_x(60.0, "larger", 200, 100), Some(60.0));
    // Portrait: the smaller side is x.
    assert_eq!(fov_to_x(60.0, "smaller", 100, 200), Some(60.0));
    assert!((fov_to_x(60.0, "larger", 100, 200).unwrap() - atan2x(0.5 * tan(60.0))).abs() < 1e-9);
    // Diagonal 90°: half-diagonal tangent 1 = hypot(tx, tx/2).
    let d = fov_to_x(90.0, "diagonal", 200, 100).unwrap();
    assert!((d - atan2x(1.0 / 1.25f64.sqrt())).abs() < 1e-9, "{d}");
    assert_eq!(fov_to_x(60.0, "z", 1, 1), None);

    let cam = |axis: &str| {
        scene(&format!(
                r#"<sensor type="perspective"><float name="fov" value="60"/><string name="fov_axis" value="{axis}"/>
                   <film type="hdrfilm"><integer name="width" value="200"/><integer name="height" value="100"/>
                   <rfilter type="box"/></film></sensor>"#
            ))
            .description
            .camera
            .unwrap()
    };
    assert!((cam("Y").fov_x_degrees as f64 - y).abs() < 1e-4);
    assert_eq!(cam("x").fov_x_degrees, 60.0);
    assert_eq!((cam("x").width, cam("x").height), (200, 100));
}

#[test]
fn sensor_frames_match_mitsuba() {
    let cam = |t: &str| {
        scene(&format!(
            r#"<sensor type="perspective"><float name="fov" value="45"/>
                   <transform name="to_world">{t}</transform></sensor>"#
        ))
        .description
        .camera
        .unwrap()
    };
    let c = cam(r#"<lookat origin="1, 2, 3" target="4, 6, 3" up="0, 0, 1"/>"#);
    assert_close(c.eye, Vec3::new(1.0, 2.0, 3.0));
    assert_close(c.target, Vec3::new(4.0, 6.0, 3.0));
    assert_close(c.up, Vec3::Z);
    assert_eq!((c.width, c.height), (768, 576)); // Mitsuba's default film
    // lookat then a world translation: everything moves.
    let c = cam(r#"<lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/><translate y="1"/>"#);
    assert_close(c.eye, Vec3::new(0.0, 1.0, 5.0));
    assert_close(c.target, Vec3::new(0.0, 1.0, 0.0));
    // Rotating the default camera (looking down +z) by 180° about y = lookat down −z.
    let c = cam(r#"<rotate y="1" angle="180"/><translate z="5"/>"#);
    assert_close(c.eye, Vec3::new(0.0, 0.0, 5.0));
    assert_close((c.target - c.eye).normalize(), -Vec3::Z);
    assert_close(c.up, Vec3::Y);
    // Image right = forward × up = +x, as Mitsuba's image right (−local x) is.
    assert_close((c.target - c.eye).cross(c.up).normalize(), Vec3::X);

    let e = err(r#"<sensor type="perspective"><float name="fov" value="45"/>
               <transform name="to_world"><scale x="-1"/></transform></sensor>"#);
    assert!(e.starts_with("dir/test.xml:3:16: <transform name=\"to_world\">:"), "{e}");
    assert!(e.contains("mirror"), "{e}");
    let s = scene(
        r#"<sensor type="perspective"><float name="fov" value="45"/>
               <transform name="to_world"><scale value="2"/></transform></sensor>"#,
    );
    assert!(s.warnings.iter().any(|w| w.contains("scale or shear")), "{:?}", s.warnings);
}

#[test]
fn thinlens_reads_aperture_focus_and_the_perspective_parameters() {
    let cam = |params: &str| {
        scene(&format!(
            r#"<sensor type="thinlens">{params}
                   <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
                   <film type="hdrfilm"><integer name="width" value="200"/><integer name="height" value="100"/>
                   <rfilter type="box"/></film></sensor>"#
        ))
        .description
        .camera
        .unwrap()
    };
    let c = cam(r#"<float name="aperture_radius" value="0.2"/><float name="focus_distance" value="4.5"/>
                   <float name="fov" value="30"/><string name="fov_axis" value="y"/>"#);
    assert_eq!(c.kind, CameraKind::ThinLens { aperture_radius: 0.2, focus_distance: 4.5 });
    assert!((c.fov_x_degrees as f64 - fov_to_x(30.0, "y", 200, 100).unwrap()).abs() < 1e-4);
    assert_close(c.eye, Vec3::new(0.0, 0.0, 5.0));
    assert_close(c.target, Vec3::ZERO);
    // focus_distance defaults to far_clip (Mitsuba's), the field of view to 50 mm.
    let c = cam(r#"<float name="aperture_radius" value="0.1"/><float name="far_clip" value="300"/>"#);
    assert_eq!(c.kind, CameraKind::ThinLens { aperture_radius: 0.1, focus_distance: 300.0 });
    let diag = 2.0 * (43.2666f64 / 100.0).atan().to_degrees();
    assert!((c.fov_x_degrees as f64 - fov_to_x(diag, "diagonal", 200, 100).unwrap()).abs() < 1e-3);
    let c = cam(r#"<float name="aperture_radius" value="0.1"/>"#);
    assert_eq!(c.kind, CameraKind::ThinLens { aperture_radius: 0.1, focus_distance: 1e4 });
    for (params, message) in [
        ("", "needs `aperture_radius`"),
        (r#"<float name="aperture_radius" value="-0.1"/>"#, "aperture_radius: lens radius -0.1"),
        (
            r#"<float name="aperture_radius" value="0.1"/><float name="focus_distance" value="0"/>"#,
            "focus_distance: focus distance 0",
        ),
    ] {
        let e = err(&format!(r#"<sensor type="thinlens">{params}</sensor>"#));
        assert!(e.contains(message) && e.starts_with("dir/test.xml:"), "{e}");
    }
}

#[test]
fn orthographic_film_is_to_worlds_image_of_the_unit_square() {
    let cam = |t: &str, extra: &str| {
        scene(&format!(
            r#"<sensor type="orthographic">{extra}<transform name="to_world">{t}</transform>
                   <film type="hdrfilm"><integer name="width" value="200"/><integer name="height" value="100"/>
                   <rfilter type="box"/></film></sensor>"#
        ))
        .description
        .camera
        .unwrap()
    };
    // Mitsuba's example: a lookat after a scale of the film to 20 × 20 world units (local x
    // ∈ [-1, 1] → 20 units wide; local y ∈ [-1/aspect, 1/aspect] → 10 units high at 2:1).
    let c = cam(r#"<scale x="10" y="10"/><lookat origin="1, 1, 1" target="1, 2, 1" up="0, 0, 1"/>"#, "");
    assert_eq!(c.kind, CameraKind::Orthographic { half_width: 10.0, half_height: 5.0 });
    // The film starts at the near plane (0.01 along the view), as Mitsuba's rays do.
    assert_close(c.eye, Vec3::new(1.0, 1.01, 1.0));
    assert_close((c.target - c.eye).normalize(), Vec3::Y);
    assert_close(c.up, Vec3::Z);
    // Image right = forward × up = +x: Mitsuba's (local +x is the image left).
    assert_close((c.target - c.eye).cross(c.up).normalize(), Vec3::X);
    let c = cam(
        r#"<lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/>"#,
        r#"<float name="near_clip" value="0.5"/>"#,
    );
    assert_eq!(c.kind, CameraKind::Orthographic { half_width: 1.0, half_height: 0.5 });
    assert_close(c.eye, Vec3::new(0.0, 0.0, 4.5));
    for (t, message) in [
        (r#"<scale x="-1"/>"#, "mirrors space"),
        (r#"<matrix value="1 0.5 0 0  0 1 0 0  0 0 1 0  0 0 0 1"/>"#, "perpendicular"),
        (r#"<scale z="0"/>"#, "singular"),
    ] {
        let e = err(&format!(
            r#"<sensor type="orthographic"><transform name="to_world">{t}</transform></sensor>"#
        ));
        assert!(e.contains(message) && e.contains("<transform name=\"to_world\">"), "{e}");
    }
    let e = err(r#"<sensor type="orthographic"><float name="near_clip" value="0"/></sensor>"#);
    assert!(e.contains("near_clip 0 must be"), "{e}");
}

#[test]
fn focal_length_default_is_50mm_diagonal() {
    let c = scene(r#"<sensor type="perspective"><film type="hdrfilm"><rfilter type="box"/></film></sensor>"#)
        .description
        .camera
        .unwrap();
    let diag = 2.0 * (43.2666f64 / 100.0).atan().to_degrees();
    let expect = fov_to_x(diag, "diagonal", 768, 576).unwrap();
    assert!((c.fov_x_degrees as f64 - expect).abs() < 1e-3, "{}", c.fov_x_degrees);
    // 4:3 film: the horizontal extent is 4/5 of the 43.27 mm diagonal of a 36×24 mm frame.
    assert!((c.fov_x_degrees as f64 - 2.0 * (0.8 * 43.2666f64 / 100.0).atan().to_degrees()).abs() < 1e-3);
}

/// Issue 12: the film's crop window and filter reach the camera (no warnings).
#[test]
fn crop_and_filters_are_read() {
    let s = scene(
        r#"<sensor type="perspective"><float name="fov" value="45"/>
                 <film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="30"/>
                   <integer name="crop_offset_x" value="2"/><integer name="crop_offset_y" value="3"/>
                   <integer name="crop_width" value="10"/><integer name="crop_height" value="20"/>
                   <rfilter type="gaussian"><float name="stddev" value="0.7"/></rfilter></film></sensor>
               <shape type="rectangle"/>"#,
    );
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let c = s.description.camera.unwrap();
    assert_eq!((c.width, c.height), (40, 30));
    let crop = opticks_core::sensor::Crop { x: 2, y: 3, width: 10, height: 20 };
    assert_eq!(c.film.crop, Some(crop));
    assert_eq!(c.film.filter, opticks_core::sensor::Filter::Gaussian { stddev: 0.7 });
    let tent = scene(
        r#"<sensor type="perspective"><film type="hdrfilm"><rfilter type="tent"/></film></sensor>
               <shape type="rectangle"/>"#,
    );
    let c = tent.description.camera.unwrap();
    assert_eq!((c.film.crop, c.film.filter), (None, opticks_core::sensor::Filter::Tent { radius: 1.0 }));
}
