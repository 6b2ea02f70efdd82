//! Panel sizes that follow the window. Every side panel's width is a fraction of the window's
//! width (remembered between runs), bounded below by a readable minimum and above so that the
//! render in the centre always keeps [`CENTRE_SHARE`] of the width: the bounds are computed so
//! that they can never cross, whatever the window size or the remembered fractions.
//!
//! egui's own resizable panels remember the width their *content* last took, which lets a panel
//! whose content is a few points wider than the panel grow by itself, frame after frame; here the
//! panels are shown at exactly the width computed from the fractions, and the resize handles
//! (drawn by [`super::panels`]) change the fractions.

use serde::{Deserialize, Serialize};

/// The share of the window's width the central view (the render) keeps at least, in every mode.
pub const CENTRE_SHARE: f32 = 0.4;

/// The width of the collapsed trace tree (a strip with one button), in points.
pub const COLLAPSED_TREE: f32 = 30.0;

/// The side panels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// Lessons and exercises (left, outermost).
    Learn,
    /// Render settings (left).
    Settings,
    /// The trace tree (left, next to the render).
    Tree,
    /// Diagram and math (right).
    Explain,
}

impl Side {
    /// Every side panel, left to right.
    pub const ALL: [Side; 4] = [Side::Learn, Side::Settings, Side::Tree, Side::Explain];

    /// The narrowest a panel is made while the window leaves room for it (points).
    pub fn min_width(self) -> f32 {
        match self {
            Side::Learn => 260.0,
            Side::Settings => 190.0,
            Side::Tree => 200.0,
            Side::Explain => 280.0,
        }
    }
}

/// The remembered panel sizes, as fractions of the window (so they follow it).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Layout {
    /// Lessons panel width / window width.
    pub learn: f32,
    /// Settings panel width / window width.
    pub settings: f32,
    /// Trace tree width / window width.
    pub tree: f32,
    /// Diagram-and-math panel width / window width.
    pub explain: f32,
    /// Math panel height / height of the diagram-and-math panel.
    pub math: f32,
    /// The same while a Monte Carlo pixel is shown: its diagrams (the hemisphere, the light's
    /// samples, the samples' plot) are the lesson, so they get more of the height by default.
    pub sampling_math: f32,
    /// The trace tree is folded to a narrow strip.
    pub tree_collapsed: bool,
}

impl Default for Layout {
    fn default() -> Self {
        Layout {
            learn: 0.25,
            settings: 0.14,
            tree: 0.16,
            explain: 0.28,
            math: 0.5,
            sampling_math: 0.35,
            tree_collapsed: false,
        }
    }
}

/// A fraction read from a file: finite and within `lo..=hi`, else `default`.
fn sane(x: f32, lo: f32, hi: f32, default: f32) -> f32 {
    if x.is_finite() && x >= lo && x <= hi {
        x
    } else {
        default
    }
}

impl Layout {
    /// The layout presentation mode starts with: a large render and diagram, a large math panel,
    /// the trace tree folded away.
    pub fn presentation() -> Layout {
        Layout {
            explain: 0.46,
            math: 0.45,
            sampling_math: 0.3,
            tree_collapsed: true,
            ..Layout::default()
        }
    }

    /// The same layout with every value a remembered file could have spoiled (not a number,
    /// negative, larger than the window) replaced by its default.
    pub fn validated(self) -> Layout {
        let d = Layout::default();
        Layout {
            learn: sane(self.learn, 0.02, 0.6, d.learn),
            settings: sane(self.settings, 0.02, 0.6, d.settings),
            tree: sane(self.tree, 0.02, 0.6, d.tree),
            explain: sane(self.explain, 0.02, 0.6, d.explain),
            math: sane(self.math, 0.1, 0.9, d.math),
            sampling_math: sane(self.sampling_math, 0.1, 0.9, d.sampling_math),
            tree_collapsed: self.tree_collapsed,
        }
    }

    /// The remembered fraction of `side`.
    pub fn fraction(&self, side: Side) -> f32 {
        match side {
            Side::Learn => self.learn,
            Side::Settings => self.settings,
            Side::Tree => self.tree,
            Side::Explain => self.explain,
        }
    }

    fn fraction_mut(&mut self, side: Side) -> &mut f32 {
        match side {
            Side::Learn => &mut self.learn,
            Side::Settings => &mut self.settings,
            Side::Tree => &mut self.tree,
            Side::Explain => &mut self.explain,
        }
    }

    /// The widths (points) of the `shown` panels in a window `width` points wide, in the order
    /// of `shown`. Each is its fraction of the window, at least its minimum; if together they
    /// would take more than `1 − CENTRE_SHARE` of the width they are all scaled down to fit,
    /// minimums included, so the centre keeps its share at any width. A collapsed tree is
    /// [`COLLAPSED_TREE`] wide (less in a window too narrow even for that).
    pub fn widths(&self, width: f32, shown: &[Side]) -> Vec<f32> {
        let width = if width.is_finite() {
            width.max(0.0)
        } else {
            0.0
        };
        let v = self.validated();
        let budget = width * (1.0 - CENTRE_SHARE);
        let wanted: Vec<f32> = shown
            .iter()
            .map(|&s| {
                if s == Side::Tree && v.tree_collapsed {
                    COLLAPSED_TREE
                } else {
                    (v.fraction(s) * width).max(s.min_width())
                }
            })
            .collect();
        let total: f32 = wanted.iter().sum();
        let k = if total > budget && total > 0.0 {
            budget / total
        } else {
            1.0
        };
        wanted.iter().map(|w| (w * k).floor()).collect()
    }

    /// The user dragged `side`'s edge so that it would be `wanted` points wide, in a window
    /// `width` points wide where the other shown panels take `others` points: the fraction
    /// follows, as far as the centre's share allows.
    pub fn drag(&mut self, side: Side, wanted: f32, width: f32, others: f32) {
        if !(width.is_finite() && width > 1.0 && wanted.is_finite()) {
            return;
        }
        let room = (width * (1.0 - CENTRE_SHARE) - others).max(0.0);
        let w = wanted.min(room).max(side.min_width().min(room));
        *self.fraction_mut(side) = (w / width).clamp(0.02, 0.6);
    }

    /// The math panel's height (points) in a diagram-and-math panel `height` points high: its
    /// fraction ([`Layout::sampling_math`] when `sampling`, a Monte Carlo pixel, is shown),
    /// leaving the diagram at least a third.
    pub fn math_height(&self, height: f32, sampling: bool) -> f32 {
        let height = if height.is_finite() {
            height.max(0.0)
        } else {
            0.0
        };
        let v = self.validated();
        let fraction = if sampling { v.sampling_math } else { v.math };
        (fraction * height)
            .min(height * 0.67)
            .max((120.0f32).min(height * 0.5))
            .floor()
    }

    /// The user dragged the math panel's top edge to make it `wanted` points high in a panel
    /// `height` points high (while a Monte Carlo pixel is shown when `sampling`: that fraction
    /// is remembered apart).
    pub fn drag_math(&mut self, wanted: f32, height: f32, sampling: bool) {
        if height.is_finite() && height > 1.0 && wanted.is_finite() {
            let f = (wanted / height).clamp(0.15, 0.67);
            if sampling {
                self.sampling_math = f;
            } else {
                self.math = f;
            }
        }
    }
}

/// The window's height in points at zoom 1 (its height in pixels over the display's own
/// pixels per point): what presentation mode's scale is chosen against.
pub fn window_height_at_zoom_1(ctx: &egui::Context) -> f32 {
    let native = ctx.native_pixels_per_point().unwrap_or(1.0);
    let native = if native.is_finite() && native > 0.0 {
        native
    } else {
        1.0
    };
    ctx.viewport_rect().height() * ctx.pixels_per_point() / native
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: [Side; 4] = Side::ALL;

    #[test]
    fn the_centre_keeps_its_share_at_every_width() {
        for w in [
            0.0, 1.0, 320.0, 640.0, 800.0, 1024.0, 1280.0, 1920.0, 3840.0, 8192.0,
        ] {
            for layout in [Layout::default(), Layout::presentation()] {
                let ws = layout.widths(w, &ALL);
                let sum: f32 = ws.iter().sum();
                assert!(sum <= w * 0.6 + 1e-3, "{w}: {ws:?}");
                assert!(ws.iter().all(|x| *x >= 0.0));
            }
        }
    }

    #[test]
    fn spoiled_fractions_fall_back_to_the_defaults() {
        let bad = Layout {
            learn: f32::NAN,
            settings: -3.0,
            tree: 40.0,
            explain: f32::INFINITY,
            math: 0.0,
            sampling_math: f32::NAN,
            tree_collapsed: false,
        };
        assert_eq!(bad.validated(), Layout::default());
        // 2000 points: settings, tree and explain at 0.14, 0.16 and 0.28 of the width fit in
        // the 60 % the centre leaves.
        assert_eq!(
            bad.widths(2000.0, &[Side::Settings, Side::Tree, Side::Explain]),
            vec![280.0, 320.0, 560.0]
        );
    }

    #[test]
    fn minimums_hold_while_there_is_room_and_give_way_when_there_is_not() {
        let l = Layout::default();
        // 1280 wide, settings + tree + explain: 0.14 · 1280 = 179.2 → its minimum 190, then
        // 204.8 → 204.8 (above 200) and 358.4: 753.2 ≤ 768 (60 %), no scaling.
        assert_eq!(
            l.widths(1280.0, &[Side::Settings, Side::Tree, Side::Explain]),
            vec![190.0, 204.0, 358.0]
        );
        // 1024 wide: 190 + 200 + 286.72 = 676.72 > 614.4, all scaled by 614.4 / 676.72:
        // 172.5, 181.6, 260.3 → floor.
        assert_eq!(
            l.widths(1024.0, &[Side::Settings, Side::Tree, Side::Explain]),
            vec![172.0, 181.0, 260.0]
        );
    }

    #[test]
    fn a_drag_moves_the_fraction_but_never_past_the_centre() {
        let mut l = Layout::default();
        l.drag(Side::Tree, 300.0, 1500.0, 500.0);
        assert_eq!(l.tree, 0.2);
        // 1000 wide, others 500: room 100 → 100 wide even though the minimum is 200.
        l.drag(Side::Tree, 900.0, 1000.0, 500.0);
        assert_eq!(l.tree, 0.1);
        l.drag(Side::Tree, f32::NAN, 1000.0, 0.0);
        assert_eq!(l.tree, 0.1);
    }

    #[test]
    fn a_monte_carlo_pixel_keeps_its_own_math_share() {
        // Presentation mode: 600 points high, the math 0.45 of it for a Whitted pixel, 0.3 for
        // a Monte Carlo one (the diagram gets 420 points).
        let mut l = Layout::presentation();
        assert_eq!(l.math_height(600.0, false), 270.0);
        assert_eq!(l.math_height(600.0, true), 180.0);
        // Dragging while a Monte Carlo pixel is shown moves only that share.
        l.drag_math(240.0, 600.0, true);
        assert_eq!((l.math, l.sampling_math), (0.45, 0.4));
        l.drag_math(120.0, 600.0, false);
        assert_eq!((l.math, l.sampling_math), (0.2, 0.4));
        // An old preferences file without the key reads with the default.
        let old: Layout = serde_json::from_str(r#"{"math": 0.3}"#).unwrap();
        assert_eq!((old.math, old.sampling_math), (0.3, 0.35));
    }
}
