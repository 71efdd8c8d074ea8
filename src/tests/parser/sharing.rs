//! Materials and finishes shared between blocks: only equal ones, bit for bit.

use super::{ok, sphere_with, spheres, v};

#[test]
fn only_equal_materials_are_shared() {
    let diff = " diff= 0.5\n";
    let s = ok(&spheres(&[
        ("1 0 0", diff),
        ("1 0 0", diff),
        ("0 1 0", diff),
        ("1 0 0", diff),
    ]));
    // A whole material is shared with an equal one, just before it or not ...
    let materials: Vec<_> = s.objects().iter().map(|o| o.material).collect();
    assert_eq!(materials, vec![0, 0, 1, 0]);
    let colors: Vec<_> = s.materials().map(|m| m.color).collect();
    assert_eq!(colors, vec![v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)]);
    // ... and its keys other than the colour with every other.
    assert_eq!(s.finish_count(), 1);
    assert!(s.materials().all(|m| m.diff == 0.5));
}

#[test]
fn equal_finishes_far_apart_in_the_file_are_shared() {
    let glass = " refr= 0.9\n rindex= 1.5\n absor= 0.1 0.2 0.3\n spec= 0.25\n";
    let mut text = sphere_with("1 0 0", glass);
    for i in 0..50 {
        text += &sphere_with(&format!("0 {} 0", i as f64 / 50.0), " diff= 0.7\n");
        text += "primitive plane\n N= 0 0 1\n refl= 0.5\n drefl= 0.1\nend\n";
    }
    text += &sphere_with("0 0 1", glass);
    let s = ok(&text);
    assert_eq!(s.objects().len(), 102);
    assert_eq!(s.finish_count(), 3);
    // Every sphere its own material (its own colour), the planes one.
    assert_eq!(s.material_count(), 53);
    let plane = s.objects()[2].material;
    assert!(
        s.objects()[2..101]
            .iter()
            .step_by(2)
            .all(|o| o.material == plane)
    );
    let first = s.material_of(&s.objects()[0]);
    let last = s.material_of(&s.objects()[101]);
    assert_eq!(
        (first.color, last.color),
        (v(1.0, 0.0, 0.0), v(0.0, 0.0, 1.0))
    );
    for m in [first, last] {
        assert_eq!((m.refr, m.rindex, m.spec), (0.9, 1.5, 0.25));
        assert_eq!(m.absor, v(0.1, 0.2, 0.3));
        assert_eq!((m.diff, m.refl, m.drefl, m.texture), (0.0, 0.0, 0.0, None));
    }
    let plane = s.material_of(&s.objects()[100]);
    assert_eq!((plane.refl, plane.drefl, plane.diff), (0.5, 0.1, 0.0));
}

#[test]
fn different_colours_with_one_finish_cost_one_finish() {
    let colors: Vec<_> = (0..300)
        .map(|i| v(i as f64 / 300.0, 1.0 - i as f64 / 300.0, 0.5))
        .collect();
    let text: String = colors
        .iter()
        .map(|c| {
            sphere_with(
                &format!("{} {} {}", c.x, c.y, c.z),
                " diff= 0.9\n spec= 0.1\n",
            )
        })
        .collect();
    let s = ok(&text);
    assert_eq!((s.material_count(), s.finish_count()), (300, 1));
    for (o, c) in s.objects().iter().zip(&colors) {
        let m = s.material_of(o);
        assert_eq!((m.color, m.diff, m.spec), (*c, 0.9, 0.1));
    }
}

#[test]
fn textured_and_untextured_materials_never_share() {
    let s = ok(&spheres(&[
        ("1 1 1", " diff= 0.5\n texture= tiny.bmp\n"),
        ("1 1 1", " diff= 0.5\n"),
        ("0 1 1", " diff= 0.5\n texture= tiny.bmp\n"),
        ("0 1 1", " diff= 0.5\n"),
    ]));
    assert_eq!(s.finish_count(), 2);
    assert_eq!(s.material_count(), 4);
    let textures: Vec<_> = s
        .objects()
        .iter()
        .map(|o| s.material_of(o).texture)
        .collect();
    assert_eq!(textures, vec![Some(0), None, Some(0), None]);
}

#[test]
fn sharing_is_bit_exact_so_minus_zero_keeps_its_sign() {
    // -0 == 0 as numbers, but 1/-0 is -inf: nothing is shared that is not
    // the same bits, so every value is the one the file gave.
    let s = ok(&spheres(&[
        ("0 0 0", " diff= 0\n"),
        ("-0 0 0", " diff= 0\n"),
        ("-0 0 0", " diff= -0\n"),
        ("-0 0 0", " diff= 0\n"),
    ]));
    let materials: Vec<_> = s.objects().iter().map(|o| o.material).collect();
    assert_eq!(materials, vec![0, 1, 2, 1]);
    assert_eq!(s.finish_count(), 2);
    let m: Vec<_> = s.materials().collect();
    assert!(m[0].color.x.is_sign_positive() && m[1].color.x.is_sign_negative());
    assert!(m[1].diff.is_sign_positive() && m[2].diff.is_sign_negative());
}
