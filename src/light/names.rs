//! A scene's lights in one short line: each by name where there are few, counted by kind where
//! there are many (a scene of a thousand lanterns would print a thousand names).

use super::LightLabel;

/// Most lights a line names one by one.
pub const NAMED: usize = 8;

/// `labels` (in light order) as one line: "sun, spot 1, point 1" up to [`NAMED`] lights, past
/// that each kind once, in the order it first comes: its name where it is alone, else its count
/// ("sun, 1,024 point lights").
#[must_use]
pub fn lights_line(labels: &[LightLabel]) -> String {
    if labels.len() <= NAMED {
        return labels.iter().map(ToString::to_string).collect::<Vec<_>>().join(", ");
    }
    let mut kinds: Vec<(LightLabel, usize)> = Vec::new();
    for label in labels {
        match kinds.iter_mut().find(|(first, _)| first.word == label.word) {
            Some((_, n)) => *n += 1,
            None => kinds.push((*label, 1)),
        }
    }
    let each = kinds.iter().map(|(first, n)| match n {
        1 => first.to_string(),
        n => format!("{} {} lights", grouped(*n), first.word),
    });
    each.collect::<Vec<_>>().join(", ")
}

/// `n` with its thousands set apart by commas ("1,024").
fn grouped(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn label(word: &'static str, number: usize) -> LightLabel {
        LightLabel { word, number, bare: number == 1 && word == "sun" }
    }

    #[test]
    fn few_lights_are_named_and_many_are_counted_by_kind() {
        assert_eq!(lights_line(&[]), "");
        let few = [label("sun", 1), label("spot", 1), label("point", 1)];
        assert_eq!(lights_line(&few), "sun, spot 1, point 1");
        let mut many = vec![label("sun", 1)];
        many.extend((1..=1024).map(|k| label("point", k)));
        many.extend((1..=2).map(|k| label("spot", k)));
        assert_eq!(lights_line(&many), "sun, 1,024 point lights, 2 spot lights");
        let nine: Vec<_> = (1..=9).map(|k| label("spot", k)).collect();
        assert_eq!(lights_line(&nine), "9 spot lights");
    }

    #[test]
    fn counts_are_grouped_by_thousands() {
        let cases = [(0, "0"), (7, "7"), (999, "999"), (1000, "1,000"), (1024, "1,024"), (1_234_567, "1,234,567")];
        for (n, text) in cases {
            assert_eq!(grouped(n), text);
        }
    }
}
