//! Peridynamics validation: gamma from exact partial areas, constants, energy density of bulk nodes,
//! pure PD model under linear fields.

use rustfrac_core::pd::{family_stencil, gamma};

#[test]
fn gamma_from_exact_partial_areas() {
    // closed-forms.md values (exact areas); the paper prints 0.988895997195466 for m = 4
    let expected = [
        (2, 0.950650952289580),
        (3, 0.978471034140134),
        (4, 0.988895997198035),
        (5, 0.993153917307724),
        (6, 0.995345123916148),
    ];
    for (m, g_ref) in expected {
        let g = gamma(m).unwrap();
        println!(
            "m = {m}: gamma = {g:.15} (reference {g_ref:.15}, diff {:.2e}), family {}",
            g - g_ref,
            family_stencil(m).len()
        );
        assert!((g - g_ref).abs() < 1e-10, "m = {m}: {g} vs {g_ref}");
    }
    let g4 = gamma(4).unwrap();
    assert!((g4 - 0.988895997195466).abs() < 1e-10);
    assert!(gamma(0).is_err());
}
