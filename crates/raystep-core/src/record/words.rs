//! The shared vocabulary: one name per ray kind, one wording per kernel outcome. The trace
//! tree, the math panel, the diagrams and `raystep intersect` all take their words from here,
//! so a class reads the same sentence for the same outcome wherever it looks.
//!
//! ```
//! use raystep_core::record::RayKind;
//! use raystep_core::record::words;
//! use raystep_core::shapes::RootChoice;
//!
//! assert_eq!(RayKind::Shadow.name(), "shadow");
//! assert_eq!(
//!     words::root_choice(RootChoice::FarRoot),
//!     "the origin is inside the sphere: the ray leaves it at the far root"
//! );
//! ```

use super::steps::{NodeAction, RayKind};
use crate::shapes::{RootChoice, SphereCase};

impl RayKind {
    /// The kind's name as every reader writes it: `primary`, `shadow`, `reflection`,
    /// `refraction`, `diffuse`, `glossy` (also its name in trace files).
    pub fn name(self) -> &'static str {
        match self {
            RayKind::Primary => "primary",
            RayKind::Shadow => "shadow",
            RayKind::Reflection => "reflection",
            RayKind::Refraction => "refraction",
            RayKind::Diffuse => "diffuse",
            RayKind::Glossy => "glossy",
        }
    }
}

/// What the sign of the ray–sphere discriminant Δ says.
pub fn sphere_case(case: SphereCase) -> &'static str {
    match case {
        SphereCase::Miss => "Δ < 0: no real roots, the ray's line passes the sphere by",
        SphereCase::Tangent => "Δ = 0: one double root, the line touches the sphere",
        SphereCase::EnterExit => "Δ > 0: two roots, the line enters and leaves the sphere",
    }
}

/// Which root the ray–sphere test took, and why.
pub fn root_choice(choice: RootChoice) -> &'static str {
    match choice {
        RootChoice::NoRoots => "no real roots: a miss",
        RootChoice::NearRoot => {
            "the near root is ahead and nearer than any hit so far: the ray enters the sphere there"
        }
        RootChoice::FarRoot => "the origin is inside the sphere: the ray leaves it at the far root",
        RootChoice::Behind => {
            "both roots are at or behind the origin: the sphere is behind the ray, a miss"
        }
        RootChoice::BeyondTMax => {
            "the usable root is beyond the closest hit so far: something nearer was already hit, a miss"
        }
    }
}

/// Which root the ray–sphere test took, and why, on a ray of kind `kind`. A shadow ray ends
/// just short of the light it aims at (its t_max is not a closest hit): a root at or beyond
/// that end is the light itself, or something behind it, and does not block it.
pub fn root_choice_on(choice: RootChoice, kind: RayKind) -> &'static str {
    match (choice, kind) {
        (RootChoice::BeyondTMax, RayKind::Shadow) => SHADOW_BEYOND,
        _ => root_choice(choice),
    }
}

/// Why a surface a shadow ray meets at or beyond its t_max does not block it.
pub const SHADOW_BEYOND: &str = "the usable root is at or beyond the shadow ray's end (t_max, just short of the point on the light): this is the light itself or something behind it, not between the surface and the light — not in the way";

/// What an accelerator's traversal did with a node (a BVH box or a bounding sphere) on a ray of
/// kind `kind`: a node pushed for later was the farther of two siblings the ray hits, or — on a
/// shadow ray, which looks in the farther first — the nearer.
pub fn node_action(action: NodeAction, kind: RayKind) -> &'static str {
    match action {
        NodeAction::Culled => "culled: nothing inside is tested",
        NodeAction::Descend => "hit: descend into its children",
        NodeAction::Pushed if kind == RayKind::Shadow => {
            "hit, but nearer than its sibling, and a shadow ray looks in the farther first: pushed for later"
        }
        NodeAction::Pushed => "hit, but farther than its sibling: pushed for later",
        NodeAction::TestPrimitives => "hit: test its primitives",
    }
}

/// The name of an axis (0, 1, 2 → x, y, z; anything else "?").
pub fn axis(a: u8) -> &'static str {
    ["x", "y", "z"].get(a as usize).copied().unwrap_or("?")
}

/// Step `k` of a trace of `len` steps, as every reader numbers it: `step 3 of 0–15`. Steps are
/// counted from 0 over the whole timeline (spawn steps included), as the app's step bar and
/// step list show them, `raystep trace` prints them (`[3]`) and `--step K` takes them.
pub fn step_of(k: usize, len: usize) -> String {
    format!("step {k} of 0–{}", len.saturating_sub(1))
}

/// A wording as a sentence: capital first letter, full stop.
pub fn sentence(words: &str) -> String {
    let mut c = words.chars();
    match c.next() {
        Some(first) => format!("{}{}.", first.to_uppercase(), c.as_str()),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The names are the trace format's names: a reader's word and the file agree.
    #[test]
    fn ray_kind_names_are_the_serialized_names() {
        for k in [
            RayKind::Primary,
            RayKind::Shadow,
            RayKind::Reflection,
            RayKind::Refraction,
        ] {
            assert_eq!(
                serde_json::to_string(&k).unwrap(),
                format!("\"{}\"", k.name())
            );
        }
    }

    #[test]
    fn steps_are_counted_from_zero_with_the_range_shown() {
        // 148 steps are numbered 0 … 147: the last one is "147 of 0–147", never "147 of 147"
        // (which reads as a 147-step trace) or "148 of 148" (a 1-based count).
        assert_eq!(step_of(0, 148), "step 0 of 0–147");
        assert_eq!(step_of(147, 148), "step 147 of 0–147");
    }

    #[test]
    fn sentences_start_with_a_capital_and_end_with_a_full_stop() {
        assert_eq!(
            sentence(root_choice(RootChoice::NoRoots)),
            "No real roots: a miss."
        );
        assert_eq!(sentence(""), "");
    }

    #[test]
    fn misses_say_so() {
        for c in [
            RootChoice::NoRoots,
            RootChoice::Behind,
            RootChoice::BeyondTMax,
        ] {
            assert!(root_choice(c).ends_with("a miss"), "{c:?}");
        }
    }
}
