//! Bar charts as inline SVG: a panel per measure, in which each series (a planning method)
//! has one bar, side by side in the order given, in the series' colour. Every coordinate is
//! written with one decimal, so the same figures give the same bytes.

use std::fmt::Write as _;

use super::html::escape;

/// The series' colours, in order (repeated when there are more series): blue, orange,
/// teal, brown, grey, olive, navy, sand; none of them red, green or purple, which the
/// task-tree pictures use.
const COLOURS: [&str; 8] = [
    "#1f77b4", "#ff7f0e", "#17becf", "#8c564b", "#7f7f7f", "#bcbd22", "#34495e", "#d9b382",
];

const BAR: f64 = 40.0;
const GAP: f64 = 8.0;
const SIDE: f64 = 12.0;
const TOP: f64 = 40.0;
const PLOT: f64 = 140.0;
const BOTTOM: f64 = 24.0;
const MIN_WIDTH: f64 = 180.0;

/// The colour of series `i`.
pub(super) fn colour(i: usize) -> &'static str {
    COLOURS[i % COLOURS.len()]
}

/// One measure: its title, and per series its value (`None`: no bar) and how the value is
/// written above the bar.
pub(super) struct Panel {
    pub key: &'static str,
    pub title: String,
    pub values: Vec<(Option<f64>, String)>,
}

/// A panel as an `<svg class="chart">`: bars scaled to the largest value (a value of zero
/// is a one-pixel bar, so every series with a value has a bar to see), each bar a
/// `rect.bar` carrying its series' name, a number under each bar naming the series (see
/// [`legend`]).
pub(super) fn panel(p: &Panel, names: &[String]) -> String {
    let n = p.values.len();
    let width = (2.0 * SIDE + n as f64 * BAR + n.saturating_sub(1) as f64 * GAP).max(MIN_WIDTH);
    let height = TOP + PLOT + BOTTOM;
    let max = p
        .values
        .iter()
        .filter_map(|(v, _)| *v)
        .filter(|v| v.is_finite())
        .fold(0.0f64, f64::max);
    let used = n as f64 * BAR + n.saturating_sub(1) as f64 * GAP;
    let left = (width - used) / 2.0;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<svg class=\"chart\" data-measure=\"{}\" xmlns=\"http://www.w3.org/2000/svg\" \
         width=\"{width:.1}\" height=\"{height:.1}\" viewBox=\"0 0 {width:.1} {height:.1}\" \
         role=\"img\" aria-label=\"{}\">",
        p.key,
        escape(&p.title)
    );
    let _ = writeln!(
        out,
        "<text class=\"title\" x=\"{:.1}\" y=\"18.0\" text-anchor=\"middle\">{}</text>",
        width / 2.0,
        escape(&p.title)
    );
    let base = TOP + PLOT;
    let _ = writeln!(
        out,
        "<line class=\"axis\" x1=\"{:.1}\" y1=\"{base:.1}\" x2=\"{:.1}\" y2=\"{base:.1}\" \
         stroke=\"#555555\"/>",
        left - GAP / 2.0,
        left + used + GAP / 2.0
    );
    for (i, ((v, text), name)) in p.values.iter().zip(names).enumerate() {
        let x = left + i as f64 * (BAR + GAP);
        let mid = x + BAR / 2.0;
        if let Some(v) = v.filter(|v| v.is_finite()) {
            let h = if max > 0.0 {
                (v.max(0.0) / max * PLOT).max(1.0)
            } else {
                1.0
            };
            let y = base - h;
            let _ = writeln!(
                out,
                "<rect class=\"bar\" data-series=\"{}\" x=\"{x:.1}\" y=\"{y:.1}\" \
                 width=\"{BAR:.1}\" height=\"{h:.1}\" fill=\"{}\"><title>{}: {}</title></rect>",
                escape(name),
                colour(i),
                escape(name),
                escape(text)
            );
            let _ = writeln!(
                out,
                "<text class=\"value\" x=\"{mid:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>",
                y - 4.0,
                escape(text)
            );
        } else {
            let _ = writeln!(
                out,
                "<text class=\"value\" x=\"{mid:.1}\" y=\"{:.1}\" text-anchor=\"middle\">-</text>",
                base - 4.0
            );
        }
        let _ = writeln!(
            out,
            "<text class=\"series\" x=\"{mid:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>",
            base + 16.0,
            i + 1
        );
    }
    out.push_str("</svg>\n");
    out
}

/// The key to the panels: each series' number and colour, and its name.
pub(super) fn legend(names: &[String]) -> String {
    let mut out = String::from("<ol class=\"legend\">\n");
    for (i, name) in names.iter().enumerate() {
        let _ = writeln!(
            out,
            "<li><svg class=\"swatch\" xmlns=\"http://www.w3.org/2000/svg\" width=\"12\" \
             height=\"12\"><rect width=\"12\" height=\"12\" fill=\"{}\"/></svg> {}</li>",
            colour(i),
            escape(name)
        );
    }
    out.push_str("</ol>\n");
    out
}

/// One point of a front plot: its x (human steps), its y (success in [0, 1]) and its title.
pub(super) struct Point {
    pub x: u32,
    pub y: f64,
    pub title: String,
}

const FRONT_WIDTH: f64 = 420.0;
const FRONT_HEIGHT: f64 = 260.0;
const FRONT_LEFT: f64 = 56.0;
const FRONT_RIGHT: f64 = 20.0;
const FRONT_TOP: f64 = 34.0;
const FRONT_BOTTOM: f64 = 44.0;

/// A success for people: 6 decimals, or 4 significant digits in scientific notation below
/// 0.001 (long trees have tiny successes).
pub(super) fn success_text(x: f64) -> String {
    if x != 0.0 && x.abs() < 1e-3 {
        format!("{x:.3e}")
    } else {
        format!("{x:.6}")
    }
}

/// The y axis of a front: linear from 0 to 1 (or to the largest y when it is below 0.5), or,
/// when the positive values span more than two orders of magnitude or all lie below 0.001
/// (long trees have tiny successes), logarithmic over the decades that hold them (a value of
/// 0 is drawn at the bottom).
enum Scale {
    Linear(f64),
    Log(i32, i32),
}

impl Scale {
    fn of(values: impl Iterator<Item = f64>) -> Self {
        let pos: Vec<f64> = values.filter(|y| y.is_finite() && *y > 0.0).collect();
        let (lo, hi) = pos
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &y| (a.min(y), b.max(y)));
        if pos.is_empty() {
            return Self::Linear(1.0);
        }
        if hi < 1e-3 || hi / lo > 100.0 {
            // Decades: exponents of 10 within i32 for every finite positive f64.
            let a = lo.log10().floor() as i32;
            let b = (hi.log10().ceil() as i32).max(a + 1);
            return Self::Log(a, b);
        }
        Self::Linear(if hi < 0.5 { hi } else { 1.0 })
    }

    /// Where `y` lies, from 0 (bottom) to 1 (top).
    fn at(&self, y: f64) -> f64 {
        if !y.is_finite() || y <= 0.0 {
            return 0.0;
        }
        match *self {
            Self::Linear(max) => (y / max).clamp(0.0, 1.0),
            Self::Log(a, b) => ((y.log10() - f64::from(a)) / f64::from(b - a)).clamp(0.0, 1.0),
        }
    }

    /// About five labelled ticks: (value, label).
    fn ticks(&self) -> Vec<(f64, String)> {
        match *self {
            Self::Linear(max) => (0..=4)
                .map(|i| {
                    let y = f64::from(i) / 4.0 * max;
                    let label = if max < 0.5 {
                        success_text(y)
                    } else {
                        format!("{y:.2}")
                    };
                    (y, label)
                })
                .collect(),
            Self::Log(a, b) => {
                let step = usize::try_from((b - a + 3) / 4).unwrap_or(1).max(1);
                (a..=b)
                    .step_by(step)
                    .map(|k| (10f64.powi(k), format!("1e{k}")))
                    .collect()
            }
        }
    }
}

/// A front as an `<svg class="chart front">`: x from 0 to the largest x (at least 1), y
/// (success) on a [`Scale`], each point a `circle.point` carrying `data-x` and `data-y`
/// (the values, y in Rust's shortest exponent form, which reads back exactly), joined by a
/// staircase (`path.front`): success holds between points.
pub(super) fn front(title: &str, x_title: &str, y_title: &str, points: &[Point]) -> String {
    let max_x = points.iter().map(|p| p.x).max().unwrap_or(0).max(1);
    let (w, h) = (FRONT_WIDTH, FRONT_HEIGHT);
    let plot_w = w - FRONT_LEFT - FRONT_RIGHT;
    let plot_h = h - FRONT_TOP - FRONT_BOTTOM;
    let px = |x: u32| FRONT_LEFT + f64::from(x) / f64::from(max_x) * plot_w;
    let scale = Scale::of(points.iter().map(|p| p.y));
    let py = |y: f64| FRONT_TOP + (1.0 - scale.at(y)) * plot_h;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<svg class=\"chart front\" data-measure=\"front\" xmlns=\"http://www.w3.org/2000/svg\" \
         width=\"{w:.1}\" height=\"{h:.1}\" viewBox=\"0 0 {w:.1} {h:.1}\" role=\"img\" \
         aria-label=\"{}\">",
        escape(title)
    );
    let _ = writeln!(
        out,
        "<text class=\"title\" x=\"{:.1}\" y=\"18.0\" text-anchor=\"middle\">{}</text>",
        w / 2.0,
        escape(title)
    );
    let base = FRONT_TOP + plot_h;
    let _ = writeln!(
        out,
        "<line class=\"axis\" x1=\"{FRONT_LEFT:.1}\" y1=\"{base:.1}\" x2=\"{:.1}\" \
         y2=\"{base:.1}\" stroke=\"#555555\"/>",
        FRONT_LEFT + plot_w
    );
    let _ = writeln!(
        out,
        "<line class=\"axis\" x1=\"{FRONT_LEFT:.1}\" y1=\"{FRONT_TOP:.1}\" x2=\"{FRONT_LEFT:.1}\" \
         y2=\"{base:.1}\" stroke=\"#555555\"/>"
    );
    for (y, label) in scale.ticks() {
        let _ = writeln!(
            out,
            "<text class=\"tick\" x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{label}</text>",
            FRONT_LEFT - 6.0,
            py(y) + 4.0
        );
    }
    // At most about 10 labelled ticks on x.
    let step = max_x.div_ceil(10).max(1);
    let mut x = 0;
    while x <= max_x {
        let _ = writeln!(
            out,
            "<text class=\"tick\" x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{x}</text>",
            px(x),
            base + 14.0
        );
        x += step;
    }
    let _ = writeln!(
        out,
        "<text class=\"axis-title\" x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>",
        FRONT_LEFT + plot_w / 2.0,
        h - 8.0,
        escape(x_title)
    );
    let _ = writeln!(
        out,
        "<text class=\"axis-title\" x=\"14.0\" y=\"{:.1}\" text-anchor=\"middle\" \
         transform=\"rotate(-90 14.0 {:.1})\">{}</text>",
        FRONT_TOP + plot_h / 2.0,
        FRONT_TOP + plot_h / 2.0,
        escape(y_title)
    );
    if let Some(first) = points.first() {
        let mut d = format!("M {:.1} {:.1}", px(first.x), py(first.y));
        for pair in points.windows(2) {
            let _ = write!(d, " H {:.1} V {:.1}", px(pair[1].x), py(pair[1].y));
        }
        let _ = writeln!(
            out,
            "<path class=\"front\" d=\"{d}\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\"/>",
            colour(0)
        );
    }
    for p in points {
        let _ = writeln!(
            out,
            "<circle class=\"point\" data-x=\"{}\" data-y=\"{:e}\" cx=\"{:.1}\" cy=\"{:.1}\" \
             r=\"5.0\" fill=\"{}\"><title>{}</title></circle>",
            p.x,
            p.y,
            px(p.x),
            py(p.y),
            colour(1),
            escape(&p.title)
        );
    }
    out.push_str("</svg>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(n: usize) -> Vec<String> {
        (0..n).map(|i| format!("m<{i}>")).collect()
    }

    #[test]
    fn a_bar_per_series_with_a_value() {
        let p = Panel {
            key: "solved",
            title: "goals solved".into(),
            values: vec![
                (Some(3.0), "3".into()),
                (None, "-".into()),
                (Some(0.0), "0".into()),
            ],
        };
        let svg = panel(&p, &names(3));
        assert_eq!(svg.matches("<rect class=\"bar\"").count(), 2);
        assert!(svg.contains("m&lt;0&gt;"));
        assert!(!svg.contains("m<0>"));
        // The largest value fills the plot; zero is one pixel high.
        assert!(svg.contains(&format!("height=\"{PLOT:.1}\"")));
        assert!(svg.contains("height=\"1.0\""));
        assert_eq!(svg, panel(&p, &names(3)));
    }

    #[test]
    fn the_legend_names_every_series() {
        let l = legend(&names(9));
        assert_eq!(l.matches("<li>").count(), 9);
        assert!(l.contains(colour(8)));
    }

    #[test]
    fn a_front_has_a_circle_per_point() {
        let pts = [
            Point {
                x: 0,
                y: 0.25,
                title: "a<".into(),
            },
            Point {
                x: 2,
                y: 1.0,
                title: "b".into(),
            },
        ];
        let svg = front("t", "x", "y", &pts);
        assert_eq!(svg.matches("<circle class=\"point\"").count(), 2);
        assert!(svg.contains("data-x=\"2\" data-y=\"1e0\""), "{svg}");
        // Tiny successes: a log axis over their decades.
        let tiny = [
            Point {
                x: 0,
                y: 2.5e-73,
                title: String::new(),
            },
            Point {
                x: 1,
                y: 3.0e-70,
                title: String::new(),
            },
        ];
        let log = front("t", "x", "y", &tiny);
        assert!(log.contains(">1e-73<") && log.contains(">1e-69<"), "{log}");
        assert!(log.contains("data-y=\"2.5e-73\""));
        assert_eq!(success_text(1.5e-7), "1.500e-7");
        assert_eq!(success_text(0.25), "0.250000");
        assert!(svg.contains("a&lt;") && !svg.contains("a<"));
        assert_eq!(svg.matches("<path class=\"front\"").count(), 1);
        assert!(!front("t", "x", "y", &[]).contains("<circle"));
    }
}
