//! Shared helpers for text formats: numbered lines and fast number parsing.

/// Iterates `(1-based line number, byte offset, line)` over text, stripping
/// `\r\n`. A line that is not UTF-8 yields an error message instead.
pub struct Lines<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: u64,
}

impl<'a> Lines<'a> {
    pub fn new(bytes: &'a [u8]) -> Lines<'a> {
        Lines {
            bytes,
            pos: 0,
            line: 0,
        }
    }

    /// Bytes not yet consumed.
    pub fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    pub fn offset(&self) -> usize {
        self.pos
    }

    pub fn line(&self) -> u64 {
        self.line
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = (u64, usize, Result<&'a str, String>);

    fn next(&mut self) -> Option<Self::Item> {
        if self.pos >= self.bytes.len() {
            return None;
        }
        let start = self.pos;
        let rest = &self.bytes[start..];
        let end = rest
            .iter()
            .position(|&b| b == b'\n')
            .map_or(rest.len(), |i| i);
        self.pos = (start + end + 1).min(self.bytes.len());
        self.line += 1;
        let mut raw = &rest[..end];
        if raw.last() == Some(&b'\r') {
            raw = &raw[..raw.len() - 1];
        }
        let text = std::str::from_utf8(raw).map_err(|e| {
            format!(
                "not UTF-8 text (invalid byte at column {})",
                e.valid_up_to() + 1
            )
        });
        Some((self.line, start, text))
    }
}

/// Parses a decimal integer with optional sign.
pub fn parse_i64(s: &str) -> Option<i64> {
    let b = s.as_bytes();
    let (neg, digits) = match b.first()? {
        b'-' => (true, &b[1..]),
        b'+' => (false, &b[1..]),
        _ => (false, b),
    };
    if digits.is_empty() || digits.len() > 18 {
        return None;
    }
    let mut v: i64 = 0;
    for &d in digits {
        if !d.is_ascii_digit() {
            return None;
        }
        v = v * 10 + (d - b'0') as i64;
    }
    Some(if neg { -v } else { v })
}

/// Parses a float (Rust's correctly rounded parser).
pub fn parse_f32(s: &str) -> Option<f32> {
    s.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_and_numbers() {
        let l: Vec<_> = Lines::new(b"a\r\nb\n\nc")
            .map(|(n, o, s)| (n, o, s.unwrap()))
            .collect();
        assert_eq!(l, vec![(1, 0, "a"), (2, 3, "b"), (3, 5, ""), (4, 6, "c")]);
        assert_eq!(parse_i64("-12"), Some(-12));
        assert_eq!(parse_i64("1x"), None);
        assert_eq!(parse_i64(""), None);
        assert_eq!(parse_i64("99999999999999999999"), None);
        assert_eq!(parse_f32("1e-3"), Some(1e-3));
        assert!(Lines::new(b"\xff\n").next().unwrap().2.is_err());
    }
}
