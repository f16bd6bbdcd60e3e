//! One self-contained HTML page (no file or network is fetched to view it): for task trees,
//! per tree its picture (the tree's DOT rendered to SVG by Graphviz and inlined), its
//! numbered steps and its figures; for a comparison, the summary per method, a bar chart of
//! the methods side by side and a row per (method, goal).
//!
//! A small inline script runs when the page has loaded: it counts the drawn nodes
//! (`g.node.motion`, `g.node.object`) and the chart's bars, and of those the ones with a
//! non-empty bounding box, and writes the counts into `data-` attributes of each section and
//! of `<body>` (`data-motions`, `data-motions-shown`, `data-objects`, `data-objects-shown`,
//! `data-bars`, `data-bars-shown`, `data-points`, `data-points-shown` (the points of a
//! front plot), `data-rendered`), so that a browser's DOM shows whether
//! the page rendered.

use std::fmt::Write as _;
use std::io;

use super::chart::{self, Panel};
use super::compare::{Cell, Comparison, cell_f64, cell_int};
use super::{Failed, Format, Options, TreeDoc, TreeFormat, put};
use crate::error::Result;

/// `s` with `&`, `<`, `>`, `"` and `'` written as character references, safe as element
/// text and as a quoted attribute value.
pub(super) fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

const STYLE: &str = "\
body { font-family: system-ui, -apple-system, 'Segoe UI', Helvetica, Arial, sans-serif; \
margin: 1.5em auto; max-width: 72em; padding: 0 1em; color: #222222; background: #ffffff; }
h1 { font-size: 1.5em; }
h2 { font-size: 1.25em; border-bottom: 1px solid #cccccc; padding-bottom: 0.2em; }
h3 { font-size: 1.05em; }
section { margin-bottom: 2.5em; }
figure.picture { margin: 0; overflow-x: auto; }
figure.picture svg { max-width: 100%; height: auto; }
ol.steps { list-style: none; padding-left: 0; }
ol.steps li { margin: 0.2em 0; }
table { border-collapse: collapse; margin: 0.5em 0; }
th, td { border: 1px solid #cccccc; padding: 0.25em 0.6em; text-align: left; vertical-align: top; }
table.summary td:first-child, table.rows td:nth-child(2) { white-space: nowrap; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
th { background: #f2f2f2; }
p.error { color: #333333; background: #f7f3e3; border-left: 4px solid #b8a36a; padding: 0.4em 0.8em; }
ul.leaves { margin: 0; padding-left: 1.2em; }
div.charts { display: flex; flex-wrap: wrap; gap: 1em; }
svg.chart text { font-size: 11px; fill: #222222; }
svg.chart text.title { font-size: 12px; font-weight: bold; }
ol.legend { list-style: none; padding-left: 0; }
ol.legend li { margin: 0.15em 0; }
ol.legend li::before { content: counter(list-item) \". \"; }
";

const SCRIPT: &str = "\
(function () {
  function count(root, selector) {
    var all = root.querySelectorAll(selector), shown = 0;
    for (var i = 0; i < all.length; i++) {
      var b = all[i].getBBox();
      if (b.width > 0 && b.height > 0) { shown++; }
    }
    return [all.length, shown];
  }
  function mark(el, root) {
    var m = count(root, 'svg g.node.motion'), o = count(root, 'svg g.node.object');
    var b = count(root, 'svg.chart rect.bar');
    var p = count(root, 'svg.chart circle.point');
    el.setAttribute('data-motions', m[0]);
    el.setAttribute('data-motions-shown', m[1]);
    el.setAttribute('data-objects', o[0]);
    el.setAttribute('data-objects-shown', o[1]);
    el.setAttribute('data-bars', b[0]);
    el.setAttribute('data-bars-shown', b[1]);
    el.setAttribute('data-points', p[0]);
    el.setAttribute('data-points-shown', p[1]);
  }
  window.addEventListener('load', function () {
    var trees = document.querySelectorAll('section.tree');
    for (var i = 0; i < trees.length; i++) { mark(trees[i], trees[i]); }
    var charts = document.querySelectorAll('svg.chart');
    for (var j = 0; j < charts.length; j++) {
      var c = count(charts[j], 'rect.bar');
      charts[j].setAttribute('data-bars', c[0]);
      charts[j].setAttribute('data-bars-shown', c[1]);
    }
    mark(document.body, document);
    document.body.setAttribute('data-rendered', 'yes');
  });
})();
";

/// The whole page around `body`.
pub(super) fn page(title: &str, kind: &str, body: &str) -> String {
    let mut out = String::new();
    out.push_str("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    out.push_str("<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n");
    out.push_str("<meta name=\"generator\" content=\"foon\">\n");
    let _ = writeln!(out, "<title>{}</title>", escape(title));
    let _ = write!(out, "<style>\n{STYLE}</style>\n</head>\n");
    let _ = writeln!(out, "<body data-page=\"{kind}\">");
    let _ = writeln!(out, "<h1>{}</h1>", escape(title));
    out.push_str(body);
    let _ = write!(out, "<script>\n{SCRIPT}</script>\n</body>\n</html>\n");
    out
}

/// Graphviz's SVG as an element to inline: from `<svg` on (no XML prolog or doctype), with
/// every `id` prefixed so that several pictures on one page keep their ids apart.
pub(super) fn inline_svg(svg: &[u8], prefix: &str) -> String {
    let text = String::from_utf8_lossy(svg);
    let start = text.find("<svg").unwrap_or(0);
    text[start..]
        .replace(" id=\"", &format!(" id=\"{prefix}"))
        .trim_end()
        .to_owned()
}

/// The tree's picture, as inline SVG.
fn picture(doc: &TreeDoc<'_>, opts: &Options, prefix: &str) -> Result<String> {
    let own = Options {
        title: None,
        ..opts.clone()
    };
    let mut dot = super::dot::DotTrees::new(Format::Svg, &own, false);
    let mut svg = Vec::new();
    dot.tree(doc, &mut svg)?;
    dot.end(&mut svg)?;
    Ok(inline_svg(&svg, prefix))
}

fn row(out: &mut String, head: &str, cell: &str, num: bool) {
    let class = if num { " class=\"num\"" } else { "" };
    let _ = writeln!(
        out,
        "<tr><th scope=\"row\">{}</th><td{class}>{cell}</td></tr>",
        escape(head)
    );
}

/// One tree's section: its goal as a heading (`heading`: when the page's title is not the
/// goal already), the picture, the steps and the figures.
fn tree_section(doc: &TreeDoc<'_>, opts: &Options, i: usize, heading: bool) -> Result<String> {
    let foon = doc.foon;
    let plan = doc.plan;
    let goal = super::object_line(foon, doc.goal());
    let svg = picture(doc, opts, &format!("t{i}-"))?;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<section class=\"tree\" id=\"tree-{i}\" data-goal=\"{}\">",
        escape(&goal)
    );
    if heading {
        let _ = writeln!(s, "<h2>{}</h2>", escape(&goal));
    }
    if !plan.solved {
        let why = super::explanation_text(foon, plan);
        let why = if why.is_empty() {
            "the goal could not be made".to_owned()
        } else {
            why
        };
        let _ = writeln!(s, "<p class=\"error\">Not solved: {}</p>", escape(&why));
    }
    let _ = writeln!(s, "<figure class=\"picture\">\n{svg}\n</figure>");
    s.push_str("<h3>Steps</h3>\n");
    let steps = super::steps::lines(doc);
    if steps.is_empty() {
        s.push_str("<p class=\"steps\">No steps.</p>\n");
    } else {
        s.push_str("<ol class=\"steps\">\n");
        for l in &steps {
            let _ = writeln!(s, "<li>{}</li>", escape(l));
        }
        s.push_str("</ol>\n");
    }
    s.push_str("<h3>The tree</h3>\n<table class=\"figures\">\n");
    row(&mut s, "method", &escape(plan.query.method.as_str()), false);
    row(
        &mut s,
        "solved",
        if plan.solved { "yes" } else { "no" },
        false,
    );
    row(&mut s, "units", &doc.units().len().to_string(), true);
    row(&mut s, "height", &cell_int(plan.height), true);
    row(
        &mut s,
        "success",
        &cell_f64(plan.success, Cell::Percent),
        true,
    );
    row(&mut s, "leaf inputs", &plan.leaf_inputs.to_string(), true);
    let leaves = doc.leaves();
    let mut items = String::new();
    if leaves.is_empty() {
        items.push('-');
    } else {
        items.push_str("<ul class=\"leaves\">");
        for &o in &leaves {
            let _ = write!(items, "<li>{}</li>", escape(&super::object_line(foon, o)));
        }
        items.push_str("</ul>");
    }
    row(&mut s, "kitchen items used", &items, false);
    row(&mut s, "expanded", &plan.expanded.to_string(), true);
    row(
        &mut s,
        "peak frontier",
        &plan.peak_frontier.to_string(),
        true,
    );
    s.push_str("</table>\n</section>\n");
    Ok(s)
}

/// Task trees as one page: a section per tree, and one per goal that could not be planned
/// (with its error). Everything is kept until [`end`](TreeFormat::end), so a failure (no
/// `dot`, a picture too large) writes nothing.
pub(super) struct HtmlTrees {
    opts: Options,
    many: bool,
    body: String,
    first_goal: Option<String>,
    sections: usize,
}

impl HtmlTrees {
    pub(super) fn new(opts: &Options, many: bool) -> Self {
        Self {
            opts: opts.clone(),
            many,
            body: String::new(),
            first_goal: None,
            sections: 0,
        }
    }
}

impl TreeFormat for HtmlTrees {
    fn tree(&mut self, doc: &TreeDoc<'_>, _out: &mut dyn io::Write) -> Result<()> {
        let heading = self.many || self.opts.title.is_some();
        let section = tree_section(doc, &self.opts, self.sections, heading)?;
        self.body.push_str(&section);
        self.first_goal
            .get_or_insert_with(|| super::object_line(doc.foon, doc.goal()));
        self.sections += 1;
        Ok(())
    }

    fn failed(&mut self, f: &Failed, _out: &mut dyn io::Write) -> Result<()> {
        let goal = f.goal_text();
        let _ = writeln!(
            self.body,
            "<section class=\"failed\" id=\"tree-{}\" data-goal=\"{}\">\n<h2>{}</h2>\n\
             <p class=\"error\">Not planned ({}): {}</p>\n</section>",
            self.sections,
            escape(&goal),
            escape(&goal),
            escape(f.method.as_str()),
            escape(&f.error)
        );
        self.first_goal.get_or_insert(goal);
        self.sections += 1;
        Ok(())
    }

    fn end(&mut self, out: &mut dyn io::Write) -> Result<()> {
        let title = match (&self.opts.title, self.many, &self.first_goal) {
            (Some(t), _, _) => t.clone(),
            (None, false, Some(g)) => g.clone(),
            _ => "Task trees".to_owned(),
        };
        put(out, page(&title, "trees", &self.body).as_bytes())
    }
}

/// A table: a header row, then rows of (text, right-aligned?) cells, already escaped.
fn table(class: &str, head: &[&str], rows: &[Vec<(String, bool)>]) -> String {
    let mut s = format!("<table class=\"{class}\">\n<thead><tr>");
    for h in head {
        let _ = write!(s, "<th scope=\"col\">{}</th>", escape(h));
    }
    s.push_str("</tr></thead>\n<tbody>\n");
    for r in rows {
        s.push_str("<tr>");
        for (c, num) in r {
            let class = if *num { " class=\"num\"" } else { "" };
            let _ = write!(s, "<td{class}>{c}</td>");
        }
        s.push_str("</tr>\n");
    }
    s.push_str("</tbody>\n</table>\n");
    s
}

fn text(s: &str) -> (String, bool) {
    (escape(s), false)
}

fn num(s: &str) -> (String, bool) {
    (escape(s), true)
}

/// A comparison as one page: the summary per method (solved count, mean FU count, height,
/// success, leaf inputs, expanded, peak frontier as the memory measure, total time), a bar
/// chart of the methods side by side, and a row per (method, goal).
pub(super) fn write_comparison(
    doc: &Comparison,
    opts: &Options,
    out: &mut dyn io::Write,
) -> Result<()> {
    let title = opts
        .title
        .clone()
        .unwrap_or_else(|| "Comparison of planning methods".to_owned());
    let names: Vec<String> = doc.summary.iter().map(|s| s.method.clone()).collect();
    let mut body = String::new();
    let goals = doc.summary.first().map_or(0, |s| s.goals);
    let _ = writeln!(
        body,
        "<p class=\"about\">{} methods, {} goals. Means are over the goals each method \
         solved (expanded and peak frontier over the goals it planned); peak frontier is the \
         search's memory measure.</p>",
        names.len(),
        goals
    );
    body.push_str("<h2>Per method</h2>\n");
    let x = doc.extras();
    let extra_head = x.head();
    let summary: Vec<Vec<(String, bool)>> = doc
        .summary
        .iter()
        .map(|s| {
            let extra = s.extra_cells(x).into_iter().map(|c| num(&c));
            let mut cells = vec![
                text(&s.method),
                num(&format!("{}/{}", s.solved_count, s.goals)),
                num(&cell_f64(s.fu_count, Cell::Plain)),
                num(&cell_f64(s.height, Cell::Plain)),
                num(&cell_f64(s.success, Cell::Percent)),
                num(&cell_f64(s.leaf_inputs, Cell::Plain)),
                num(&cell_f64(s.expanded, Cell::Plain)),
                num(&cell_f64(s.peak_frontier, Cell::Plain)),
                num(&cell_f64(Some(s.seconds_total), Cell::Millis)),
            ];
            cells.extend(extra);
            cells
        })
        .collect();
    let mut head = vec![
        "method",
        "solved",
        "units (mean)",
        "height (mean)",
        "success (mean)",
        "leaf inputs (mean)",
        "expanded (mean)",
        "peak frontier (mean)",
        "time (total ms)",
    ];
    head.extend(extra_head.iter().map(String::as_str));
    body.push_str(&table("summary", &head, &summary));
    if !names.is_empty() {
        body.push_str("<h2>Side by side</h2>\n<div class=\"charts\">\n");
        let panels = [
            Panel {
                key: "solved",
                title: "goals solved".to_owned(),
                values: doc
                    .summary
                    .iter()
                    .map(|s| (Some(s.solved_count as f64), s.solved_count.to_string()))
                    .collect(),
            },
            Panel {
                key: "fu_count",
                title: "units (mean)".to_owned(),
                values: doc
                    .summary
                    .iter()
                    .map(|s| (s.fu_count, cell_f64(s.fu_count, Cell::Plain)))
                    .collect(),
            },
            Panel {
                key: "success",
                title: "success (mean)".to_owned(),
                values: doc
                    .summary
                    .iter()
                    .map(|s| (s.success, cell_f64(s.success, Cell::Percent)))
                    .collect(),
            },
            Panel {
                key: "peak_frontier",
                title: "peak frontier (mean)".to_owned(),
                values: doc
                    .summary
                    .iter()
                    .map(|s| (s.peak_frontier, cell_f64(s.peak_frontier, Cell::Plain)))
                    .collect(),
            },
        ];
        for p in &panels {
            body.push_str(&chart::panel(p, &names));
        }
        body.push_str("</div>\n");
        body.push_str(&chart::legend(&names));
    }
    body.push_str("<h2>Per goal</h2>\n");
    let rows: Vec<Vec<(String, bool)>> = doc
        .rows
        .iter()
        .map(|r| {
            let last = match &r.error {
                Some(e) => text(e),
                None => num(&cell_f64(r.seconds, Cell::Millis)),
            };
            let mut cells = vec![
                text(&r.goal),
                text(&r.method),
                text(if r.solved { "yes" } else { "no" }),
                num(&cell_int(r.fu_count)),
                num(&cell_int(r.height)),
                num(&cell_f64(r.success, Cell::Percent)),
                num(&cell_int(r.leaf_inputs)),
                num(&cell_int(r.expanded)),
                num(&cell_int(r.peak_frontier)),
                last,
            ];
            cells.extend(r.extra_cells(x).into_iter().map(|c| num(&c)));
            cells
        })
        .collect();
    let mut head = vec![
        "goal",
        "method",
        "solved",
        "units",
        "height",
        "success",
        "leaf inputs",
        "expanded",
        "peak frontier",
        "ms (or why not planned)",
    ];
    head.extend(extra_head.iter().map(String::as_str));
    body.push_str(&table("rows", &head, &rows));
    put(out, page(&title, "comparison", &body).as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escape_covers_markup_and_quotes() {
        assert_eq!(
            escape("<a href=\"x\">'&'</a>"),
            "&lt;a href=&quot;x&quot;&gt;&#39;&amp;&#39;&lt;/a&gt;"
        );
    }

    #[test]
    fn inlined_svg_drops_the_prolog_and_prefixes_ids() {
        let svg = b"<?xml version=\"1.0\"?>\n<!DOCTYPE svg>\n<svg width=\"1\">\n\
            <g id=\"node1\" class=\"node\"></g>\n</svg>\n";
        assert_eq!(
            inline_svg(svg, "t0-"),
            "<svg width=\"1\">\n<g id=\"t0-node1\" class=\"node\"></g>\n</svg>"
        );
    }

    #[test]
    fn a_comparison_page_has_a_bar_per_method_and_measure() {
        use super::super::CompareRow;
        let row = |m: &str, solved: bool| CompareRow {
            goal: "salad <greek>".into(),
            method: m.into(),
            solved,
            fu_count: solved.then_some(3),
            height: Some(2),
            success: solved.then_some(0.5),
            leaf_inputs: solved.then_some(4),
            expanded: Some(10),
            peak_frontier: Some(5),
            seconds: Some(0.001),
            error: None,
            level: 3,
            objective: None,
            bound: None,
            proven: None,
            gap: None,
            max_human: None,
            split_success: None,
            fixed_tree_success: None,
        };
        let doc = Comparison::new(vec![row("a", true), row("b", false)]);
        let mut buf = Vec::new();
        write_comparison(&doc, &Options::default(), &mut buf).unwrap();
        let page = String::from_utf8(buf).unwrap();
        // b solved nothing: it has a bar for "solved" and for the peak frontier only.
        assert_eq!(page.matches("<rect class=\"bar\"").count(), 4 + 2);
        assert!(page.contains("salad &lt;greek&gt;"));
        assert!(!page.contains("<greek>"));
        for fetch in ["src=", "<link", "url(", "@import", "href="] {
            assert!(!page.contains(fetch), "{fetch}");
        }
    }
}
