//! Values echoed in messages, clipped: a message names the key and shows
//! enough of a wrong value to recognise it, never the whole of a 600 kB string
//! pasted by mistake (a job file may hold up to `limits::MAX_JOB_BYTES`).

use std::borrow::Cow;

/// Longest echoed value, characters.
pub(crate) const MAX_ECHO: usize = 80;
/// Longest run of non-blank characters in a message, characters: more than
/// [`MAX_ECHO`] so that a long file path is still shown whole.
pub(crate) const MAX_WORD: usize = 200;
/// Longest whole message, characters.
pub const MAX_MESSAGE: usize = 1000;
/// Characters kept from the start of a clipped value.
const HEAD: usize = 60;

/// `value` itself when at most [`MAX_ECHO`] characters long, else its first 60
/// characters, `…` and its length: `xxxx… (600000 characters)`.
pub(crate) fn clip(value: &str) -> Cow<'_, str> {
    clip_to(value, MAX_ECHO)
}

/// As [`clip`], for values longer than `max` characters.
fn clip_to(value: &str, max: usize) -> Cow<'_, str> {
    let n = value.chars().count();
    if n <= max {
        return Cow::Borrowed(value);
    }
    let head: String = value.chars().take(HEAD).collect();
    Cow::Owned(format!("{head}… ({n} characters)"))
}

/// `message` with every run of non-blank characters longer than [`MAX_WORD`]
/// clipped (values are echoed without spaces by the TOML reader: `unknown
/// field `xxx…``), then, if still longer than [`MAX_MESSAGE`] characters, its
/// first 700 and last 200 characters around ` … `. A short message is returned
/// unchanged.
pub fn clip_message(message: &str) -> String {
    let mut out = String::with_capacity(message.len().min(4 * MAX_MESSAGE));
    let mut rest = message;
    while !rest.is_empty() {
        let blank = rest
            .find(|c: char| !c.is_whitespace())
            .unwrap_or(rest.len());
        out.push_str(&rest[..blank]);
        rest = &rest[blank..];
        let word = rest.find(char::is_whitespace).unwrap_or(rest.len());
        out.push_str(&clip_to(&rest[..word], MAX_WORD));
        rest = &rest[word..];
    }
    let n = out.chars().count();
    if n <= MAX_MESSAGE {
        return out;
    }
    let head: String = out.chars().take(700).collect();
    let tail: String = out.chars().skip(n - 200).collect();
    format!("{head} … {tail}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_values_and_messages_are_unchanged() {
        assert_eq!(clip("operation.depth"), "operation.depth");
        let m = "tool.diameter must be a positive number of mm, got -3";
        assert_eq!(clip_message(m), m);
        let exact = "é".repeat(MAX_ECHO);
        assert_eq!(clip(&exact), exact);
        assert_eq!(clip_message(" a\tb \n"), " a\tb \n");
        let path = format!("/{}", "d/".repeat(99));
        assert_eq!(clip_message(&path), path);
    }

    #[test]
    fn a_long_value_keeps_its_start_and_says_its_length() {
        let v = "é".repeat(600_000);
        let c = clip(&v);
        assert_eq!(c, format!("{}… (600000 characters)", "é".repeat(60)));
        let m = format!("unknown field `{v}`, expected one of `depth`, `kind`");
        let c = clip_message(&m);
        assert!(c.starts_with("unknown field `éé"), "{c}");
        assert!(
            c.ends_with("(600003 characters) expected one of `depth`, `kind`"),
            "{c}"
        );
        assert!(c.chars().count() < 150, "{c}");
    }

    #[test]
    fn a_long_message_of_short_words_is_cut_in_the_middle() {
        let m = format!("start {} end", "ab ".repeat(100_000));
        let c = clip_message(&m);
        assert_eq!(c.chars().count(), 700 + 3 + 200);
        assert!(c.starts_with("start ab"), "{c}");
        assert!(c.ends_with("ab ab  end"), "{c}");
    }
}
