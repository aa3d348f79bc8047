//! No input makes the core panic or return a non-finite or out-of-range value.
//! Inputs span the whole f32 range, NaN and ±inf included.
use mre_algorithm::estimate::AlphaBeta;
use mre_algorithm::law::{ImpactLaw, LawConfig};
use mre_algorithm::model::Branch;
use mre_algorithm::{Flags, Table};
use proptest::num::f32::ANY;
use proptest::prelude::*;

fn paper() -> Table {
    Table::paper().expect("built-in table is valid")
}

proptest! {
    #![proptest_config(mre_tests::proptest_config(2000))]

    #[test]
    fn forward_model_is_always_finite(x in ANY, v in ANY, i in ANY) {
        let r = paper().force(x, v, i);
        prop_assert!(r.force_n.is_finite());
        if !(x.is_finite() && v.is_finite() && i.is_finite()) {
            prop_assert!(r.flags.contains(Flags::NON_FINITE_INPUT));
        }
    }

    #[test]
    fn inverse_is_always_finite_and_in_range(x in ANY, target in ANY, compression in any::<bool>()) {
        let t = paper();
        let branch = if compression { Branch::Compression } else { Branch::Extension };
        let r = t.current_for_branch(x, branch, target);
        prop_assert!(r.current_a.is_finite());
        prop_assert!((0.0..=2.0).contains(&r.current_a), "{}", r.current_a);
    }

    #[test]
    fn law_commands_stay_finite_and_in_range(samples in prop::collection::vec((ANY, ANY), 1..40)) {
        let t = paper();
        let cfg = LawConfig::default();
        let mut law = ImpactLaw::new(cfg).expect("default config is valid");
        for (x, v) in samples {
            let cmd = law.step(&t, x, v);
            prop_assert!(cmd.current_a.is_finite());
            prop_assert!(cmd.current_a >= cfg.current_min_a && cmd.current_a <= cfg.current_max_a);
            let trusted = x.is_finite() && v.is_finite()
                && x >= cfg.x_valid_min_mm && x <= cfg.x_valid_max_mm && v.abs() <= cfg.v_valid_max_m_s;
            prop_assert_eq!(cmd.flags.is_fault(), !trusted);
            if !trusted {
                prop_assert_eq!(cmd.current_a, cfg.failsafe_current_a);
            }
        }
    }

    #[test]
    fn estimator_stays_finite(samples in prop::collection::vec(ANY, 1..200)) {
        let mut f = AlphaBeta::benedict_bordner(1.0e-4, 0.2);
        for z in samples {
            let (v, _) = f.update(z);
            prop_assert!(v.is_finite());
            prop_assert!(f.position_mm().is_finite());
        }
    }
}
