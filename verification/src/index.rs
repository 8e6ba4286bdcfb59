//! `index.html`: the verification suite on one self-contained page (figures inline, no
//! network): the summary table of every problem (particles, steps, wall time, headline errors,
//! observed orders, pass/fail and each failed check with its value and limit), the
//! work–precision figure, then each problem's checks and figure. The tunnel study's
//! `report.html` is laid out by the same [`document`] and [`checks_table`].

use crate::record::{Check, Outcome, Record};
use std::fmt::Write;

/// One problem as the page shows it: its record and its figure as SVG.
pub struct Entry<'a> {
    pub record: &'a Record,
    pub figure_svg: &'a str,
}

/// Text for HTML: &, <, > and " escaped.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

/// A number with four significant digits, plain where that reads well, else in e-notation.
pub fn number(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs();
    if magnitude == 0.0 {
        "0".into()
    } else if (1e-3..1e4).contains(&magnitude) {
        let digits = (3 - magnitude.log10().floor() as i32).clamp(0, 6) as usize;
        format!("{x:.digits$}")
    } else {
        format!("{x:.3e}")
    }
}

fn check_row(check: &Check) -> String {
    let status = match (&check.qualification, check.outcome()) {
        (_, Outcome::Pass) => "pass".to_string(),
        (Some(q), outcome) => format!("{}: {}", outcome.name(), escape(&q.describe())),
        (None, outcome) => outcome.name().to_string(),
    };
    format!(
        "<tr class=\"{}\"><td>{}</td><td>{}</td><td>{} {}</td><td>{}</td></tr>",
        outcome_class(check.outcome()),
        escape(&check.name),
        number(check.value),
        escape(&check.relation),
        number(check.limit),
        status
    )
}

/// The CSS class of a row or cell with `outcome`.
pub fn outcome_class(outcome: Outcome) -> &'static str {
    match outcome {
        Outcome::Pass => "pass",
        Outcome::Qualified => "qualified",
        Outcome::Fail => "fail",
    }
}

/// A self-contained page: `title`, the shared style, and `body` (HTML).
pub fn document(title: &str, body: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>{title}</title><style>\
         body{{font-family:sans-serif;margin:1.5em;max-width:1100px}}\
         table{{border-collapse:collapse;margin:0.5em 0 1em}}\
         td,th{{border:1px solid #bbb;padding:2px 6px;text-align:left;font-size:13px}}\
         tr.fail td{{background:#fde2e2}} td.fail{{color:#a00;font-weight:bold}}\
         tr.qualified td{{background:#fdf3d6}} td.qualified{{color:#850;font-weight:bold}}\
         td.pass{{color:#060}} svg{{max-width:100%;height:auto}}\
         p.stamp{{color:#a00;font-weight:bold;font-size:18px}}\
         </style></head><body>\n{body}\n</body></html>\n",
        title = escape(title)
    )
}

/// The table of `checks`: name, value, limit and result, failed rows marked.
pub fn checks_table(checks: &[Check]) -> String {
    let mut html =
        "<table><tr><th>check</th><th>value</th><th>limit</th><th>result</th></tr>\n".to_string();
    for check in checks {
        html.push_str(&check_row(check));
        html.push('\n');
    }
    html.push_str("</table>\n");
    html
}

/// The page for `entries` and the work–precision figure, with `heading` (level, threads).
pub fn page(heading: &str, entries: &[Entry], work_precision_svg: &str) -> String {
    let mut html = String::new();
    let _ = write!(
        html,
        "<h1>blastsph verification</h1>\n<p>{}</p>\n",
        escape(heading)
    );
    let count = |outcome: Outcome| {
        entries
            .iter()
            .filter(|e| e.record.outcome == outcome)
            .count()
    };
    let _ = writeln!(
        html,
        "<p>{} of {} problems pass every check; {} qualified (failed checks at bounded limits \
         of the modelled physics, each with its evidence); {} fail.</p>",
        count(Outcome::Pass),
        entries.len(),
        count(Outcome::Qualified),
        count(Outcome::Fail),
    );
    html.push_str(
        "<table><tr><th>problem</th><th>particles</th><th>steps</th><th>wall s</th>\
         <th>headline errors</th><th>observed order</th><th>result</th></tr>\n",
    );
    for entry in entries {
        let r = entry.record;
        let run = r.headline();
        let errors = r
            .headline_errors()
            .map(|(k, v)| format!("{} = {}", escape(k), number(*v)))
            .collect::<Vec<_>>()
            .join("<br>");
        let orders = r
            .order
            .iter()
            .map(|(k, v)| format!("{} = {}", escape(k), number(*v)))
            .collect::<Vec<_>>()
            .join("<br>");
        let failed: Vec<String> = r
            .checks
            .iter()
            .filter(|c| !c.pass)
            .map(|c| {
                format!(
                    "{}{}: {} (must be {} {})",
                    match c.outcome() {
                        Outcome::Qualified => "qualified: ",
                        _ => "",
                    },
                    escape(&c.name),
                    number(c.value),
                    escape(&c.relation),
                    number(c.limit)
                )
            })
            .chain(r.runs.iter().filter_map(|run| {
                run.failure
                    .as_ref()
                    .map(|f| format!("{}: stopped: {}", escape(&run.label), escape(f)))
            }))
            .collect();
        let _ = writeln!(
            html,
            "<tr><td><a href=\"#{name}\">{name}</a></td><td>{}</td><td>{}</td><td>{}</td>\
             <td>{errors}</td><td>{orders}</td><td class=\"{}\">{}{}</td></tr>",
            run.map_or(0, |run| run.n_particles),
            run.map_or(0, |run| run.steps),
            number(r.wall_s),
            outcome_class(r.outcome),
            r.outcome.name(),
            if failed.is_empty() {
                String::new()
            } else {
                format!("<br>{}", failed.join("<br>"))
            },
            name = escape(&r.problem),
        );
    }
    html.push_str("</table>\n<h2>Work against precision</h2>\n");
    html.push_str(inline(work_precision_svg));
    for entry in entries {
        let r = entry.record;
        let _ = writeln!(
            html,
            "\n<h2 id=\"{name}\">{name}: {}</h2>",
            r.outcome.name(),
            name = escape(&r.problem),
        );
        html.push_str(&checks_table(&r.checks));
        html.push_str(inline(entry.figure_svg));
    }
    document("blastsph verification", &html)
}

/// An SVG document as an inline element (without an XML declaration).
pub fn inline(svg: &str) -> &str {
    match svg.find("<svg") {
        Some(start) => &svg[start..],
        None => svg,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::{Qualification, Refinement, Run};
    use crate::Level;

    #[test]
    fn numbers_read_at_four_significant_digits() {
        assert_eq!(number(0.012345), "0.01235");
        assert_eq!(number(12.3456), "12.35");
        assert_eq!(number(7.119999999), "7.120");
        assert_eq!(number(1.5e-7), "1.500e-7");
        assert_eq!(number(0.0), "0");
    }

    #[test]
    fn the_page_escapes_text_and_lists_failed_checks() {
        let mut run = Run::new("n = 10", "", 10, 0.1);
        run.failure = Some("blow-up at <x>".into());
        let checks = vec![
            Check::at_most("error & more", 0.5, 0.1),
            Check::at_least("fine", 2.0, 1.0),
        ];
        let mut record = Record::new(
            "demo",
            Level::Quick,
            vec![run],
            Default::default(),
            checks,
            0,
        );
        record.settle();
        let svg = "<?xml version=\"1.0\"?><svg xmlns=\"http://www.w3.org/2000/svg\"></svg>";
        let html = page(
            "quick level",
            &[Entry {
                record: &record,
                figure_svg: svg,
            }],
            svg,
        );
        assert!(
            html.contains("error &amp; more: 0.5000 (must be &lt;= 0.1000)"),
            "{html}"
        );
        assert!(html.contains("blow-up at &lt;x&gt;"));
        assert!(html.contains("0 of 1 problems pass"));
        assert!(!html.contains("<?xml"));
        assert_eq!(html.matches("<svg").count(), 2);
    }

    /// A qualified check is shown with its bound, evidence and effect, and moves the record to
    /// QUALIFIED; an ordinary failure beside it still fails the record.
    #[test]
    fn a_qualified_check_is_shown_with_its_evidence_and_only_it_is_excused() {
        let settle = |checks: Vec<Check>| {
            let run = Run::new("n = 10", "", 10, 0.1);
            let mut record = Record::new(
                "demo",
                Level::Quick,
                vec![run],
                Default::default(),
                checks,
                0,
            );
            record.settle();
            record
        };
        let limit = || {
            Check::at_most("impulse", 0.3, 0.25).qualified(Qualification {
                reason: "no afterburning".into(),
                quantity: "impulse / relations".into(),
                value: 0.7,
                bound: [0.63, 1.0],
                effect: "none".into(),
                refinement: Refinement::between(0.72, 0.7),
            })
        };
        let excused = settle(vec![limit(), Check::at_least("fine", 2.0, 1.0)]);
        assert_eq!(excused.outcome, Outcome::Qualified);
        let html = page(
            "quick level",
            &[Entry {
                record: &excused,
                figure_svg: "<svg></svg>",
            }],
            "<svg></svg>",
        );
        assert!(
            html.contains("QUALIFIED: impulse / relations = 0.700 (bound 0.630–1.000)"),
            "{html}"
        );
        assert!(html.contains("no afterburning"), "{html}");
        assert!(html.contains("qualified: impulse: 0.3000"), "{html}");
        assert!(html.contains("0 of 1 problems pass every check; 1 qualified"));
        let beside = settle(vec![limit(), Check::at_least("short", 0.5, 1.0)]);
        assert_eq!(beside.outcome, Outcome::Fail);
    }
}
