//! The page of `foon split`: the Pareto front of success against human steps as a chart
//! (a point per front point, joined by a staircase), the success per budget, and each front
//! point's steps (who does what, in execution order). Self-contained like every page.

use std::fmt::Write as _;
use std::io;

use super::chart::{self, Point, success_text};
use super::html::{escape, page};
use super::{Format, Options, put};
use crate::error::{Error, Result};
use crate::index::Foon;
use crate::search::split::Split;

/// Writes the split `s` of one goal as a page (html only).
pub fn write_split(
    format: Format,
    foon: &Foon,
    s: &Split,
    opts: &Options,
    out: &mut dyn io::Write,
) -> Result<()> {
    if format != Format::Html {
        return Err(Error::Invalid(format!(
            "the {} format cannot write a split (choose from html; or --json)",
            format.as_str()
        )));
    }
    if s.goal as usize >= foon.object_count() {
        return Err(Error::Invalid(format!(
            "object {} is out of range (the FOON has {} objects)",
            s.goal,
            foon.object_count()
        )));
    }
    let goal = super::object_line(foon, s.goal);
    let title = opts
        .title
        .clone()
        .unwrap_or_else(|| format!("The robot/human split of {goal}"));
    let mut body = String::new();
    let _ = writeln!(
        body,
        "<section class=\"split\" data-goal=\"{}\" data-max-human=\"{}\">",
        escape(&goal),
        s.max_human
    );
    if !s.solved {
        body.push_str("<p class=\"error\">No tree makes the goal: there is no front.</p>\n");
    }
    let points: Vec<Point> = s
        .front
        .iter()
        .map(|p| Point {
            x: p.human,
            y: p.success,
            title: format!(
                "{} human step(s): success {}",
                p.human,
                success_text(p.success)
            ),
        })
        .collect();
    body.push_str("<h2>Success against human steps</h2>\n<div class=\"charts\">\n");
    body.push_str(&chart::front(
        "the Pareto front",
        "human steps",
        "success",
        &points,
    ));
    body.push_str("</div>\n");
    body.push_str(
        "<table class=\"budgets\">\n<thead><tr><th scope=\"col\">at most this many human \
         steps</th><th scope=\"col\">best success</th></tr></thead>\n<tbody>\n",
    );
    for (m, b) in s.best.iter().enumerate() {
        let cell = b.map_or_else(|| "-".to_owned(), success_text);
        let _ = writeln!(
            body,
            "<tr><td class=\"num\">{m}</td><td class=\"num\">{cell}</td></tr>"
        );
    }
    body.push_str("</tbody>\n</table>\n");
    for (i, p) in s.front.iter().enumerate() {
        let _ = writeln!(
            body,
            "<section class=\"point\" id=\"point-{i}\" data-human=\"{}\" data-success=\"{}\">\n\
             <h3>{} human step(s): success {}</h3>\n<ol class=\"steps\">",
            p.human,
            p.success,
            p.human,
            success_text(p.success)
        );
        for (j, t) in p.steps.iter().enumerate() {
            let times = if t.times == 1 {
                String::new()
            } else {
                format!(" (\u{d7}{})", t.times)
            };
            let _ = writeln!(
                body,
                "<li class=\"{}\">{}. <strong>{}</strong>: {} (unit {}) \u{2192} {}{}</li>",
                t.actor.as_str(),
                j + 1,
                t.actor.as_str(),
                escape(foon.motion_text(t.unit)),
                t.unit,
                escape(&super::object_line(foon, t.object)),
                times
            );
        }
        body.push_str("</ol>\n</section>\n");
    }
    body.push_str("</section>\n");
    put(out, page(&title, "split", &body).as_bytes())
}
