//! The page: the template (`template.html`) with its style (`report.css`), its script
//! (`report.js`) and the run's data (a JSON blob) put in, one self-contained file.

use serde::Serialize;

/// The page, with `{{css}}`, `{{js}}`, `{{data}}` and `{{version}}` to fill in.
const TEMPLATE: &str = include_str!("template.html");
/// The page's style.
const CSS: &str = include_str!("report.css");
/// The page's script: the animation, the plots and the tables, drawn from the data.
const JS: &str = include_str!("report.js");

/// The page showing `data`.
pub fn html(data: &impl Serialize) -> anyhow::Result<String> {
    let json = serde_json::to_string(data)?;
    Ok(fill(
        TEMPLATE,
        &[
            ("{{css}}", CSS),
            ("{{js}}", JS),
            ("{{data}}", &script_safe(&json)),
            ("{{version}}", env!("CARGO_PKG_VERSION")),
        ],
    ))
}

/// `template` with each marker replaced by its text. Only the template is searched for
/// markers, never the text put in (a model named `{{js}}` stays a name).
fn fill(template: &str, markers: &[(&str, &str)]) -> String {
    let extra: usize = markers.iter().map(|(_, text)| text.len()).sum();
    let mut page = String::with_capacity(template.len() + extra);
    let mut rest = template;
    while let Some(start) = rest.find("{{") {
        page.push_str(&rest[..start]);
        rest = &rest[start..];
        match markers.iter().find(|(marker, _)| rest.starts_with(marker)) {
            Some((marker, text)) => {
                page.push_str(text);
                rest = &rest[marker.len()..];
            }
            None => {
                page.push_str("{{");
                rest = &rest[2..];
            }
        }
    }
    page.push_str(rest);
    page
}

/// JSON that can sit inside `<script>…</script>`: every `<` written `\u003c` (JSON has `<`
/// only inside strings, where the escape reads back the same), so that no `</script>` or
/// `<!--` in a name can end or change the element.
fn script_safe(json: &str) -> String {
    json.replace('<', "\\u003c")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markers_are_replaced_once_and_only_in_the_template() {
        let page = fill(
            "a {{x}} b {{y}} {{unknown}} {{x}}",
            &[("{{x}}", "{{y}}"), ("{{y}}", "Y")],
        );
        assert_eq!(page, "a {{y}} b Y {{unknown}} {{y}}");
    }

    #[test]
    fn data_cannot_close_its_script() {
        let data = serde_json::json!({ "model": "</script><script>alert(1)</script><!--" });
        let page = html(&data).unwrap();
        let start = page.find(r#"id="zenosim-data">"#).unwrap();
        let end = start + page[start..].find("</script>").unwrap();
        let blob = &page[start + r#"id="zenosim-data">"#.len()..end];
        assert!(!blob.contains('<'), "{blob}");
        let back: serde_json::Value = serde_json::from_str(blob).unwrap();
        assert_eq!(back, data);
    }

    #[test]
    fn the_page_is_whole() {
        let page = html(&serde_json::json!({})).unwrap();
        for marker in ["{{css}}", "{{js}}", "{{data}}", "{{version}}"] {
            assert!(!page.contains(marker), "{marker}");
        }
        assert!(page.contains("zenosimReport") && page.contains(".chart canvas"));
        // Nothing is fetched: no URL but the policy that forbids them.
        assert!(!page.contains("http://") && !page.contains("https://"));
        assert!(!page.contains("src=") && !page.contains("href=\"http"));
    }
}
