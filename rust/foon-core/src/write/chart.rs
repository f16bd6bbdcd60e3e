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
}
