//! Tests of the light side's stored form: a [`MisRecord`] keeps a light vertex's class and its
//! values (to f32 roots) through a round trip, and a [`Heuristic`] survives its header byte.
//! The weights the records enter are tested against the explicit formula with the camera
//! side, in the bidirectional sensor.

use super::*;

#[test]
fn records_keep_the_class_and_the_values() {
    let h = Heuristic::Power;
    let y0 = LightVertexMis::emission_vertex(Emitter::area(0.25, 0.5), h);
    let s = LightVertexMis::at_emission(Emitter::area(0.25, 0.5), 0.8, h);
    let y1 = s.after_hit(2.0, 0.5);
    let y2 = y1.after_scatter(0.7, 0.3, 0.9, false).after_hit(1.5, 0.6);
    let y3 = y2.after_scatter(0.4, 0.8, 0.8, true).after_hit(0.5, 0.9); // after a mirror: vcm = 0
    for (state, class) in
        [(y0, VcmClass::Hit), (y1, VcmClass::Nee), (y2, VcmClass::Conn), (y3, VcmClass::Conn)]
    {
        assert_eq!(state.class(), class);
        let r = state.record();
        assert!(r.is_valid());
        let back = LightVertexMis::from_record(r, h);
        assert_eq!(back.class(), class);
        assert_eq!(back.record(), r, "a record survives a round trip exactly");
        for (a, b) in
            [(back.0.vcm, state.0.vcm), (back.0.vc[HIT], state.0.vc[HIT]), (back.0.vc[NEE], state.0.vc[NEE])]
        {
            assert!((a - b).abs() <= 2.5e-7 * b, "{a} vs {b}"); // the f32 root, squared
        }
        assert_eq!(bytemuck::bytes_of(&r).len(), 16);
    }
    assert_eq!(y3.0.vcm, 0.0);
    assert_eq!(y1.0.vcm, h.mis(2.0 / (0.5 * 0.5))); // 1/p(y₁ | y₀), NEE's x₀ density cancelling
    assert_eq!(y1.record().vcm, -8.0, "√64 stored, NEE's class in the sign");
    let bad = MisRecord { vcm: f32::NAN, ..MisRecord::default() };
    assert!(!bad.is_valid());
    assert!(!MisRecord { vc_nee: -1.0, ..MisRecord::default() }.is_valid());
}

#[test]
fn heuristics_survive_their_header_byte() {
    for h in [Heuristic::Balance, Heuristic::Power] {
        assert_eq!(Heuristic::from_code(h.code()), Some(h));
    }
    assert_eq!(Heuristic::from_code(2), None);
}
