//! The entity lump: a text list of `{ "key" "value" ... }` blocks.
//!
//! Compilers write it without escapes; values may hold any byte but `"`. We read it
//! tolerantly (lossy UTF-8, stray whitespace, a missing final NUL) but reject
//! unbalanced braces or unterminated strings with the line where they occur.

use super::BspError;

/// One entity: its key/value pairs in file order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Entity {
    pub pairs: Vec<(String, String)>,
}

impl Entity {
    /// The value of `key` (the first one, if repeated).
    pub fn get(&self, key: &str) -> Option<&str> {
        self.pairs
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// The `classname`, or "" when missing.
    pub fn classname(&self) -> &str {
        self.get("classname").unwrap_or("")
    }

    /// The `origin` key parsed as three numbers.
    pub fn origin(&self) -> Option<[f32; 3]> {
        let mut it = self.get("origin")?.split_whitespace();
        let mut o = [0.0f32; 3];
        for c in &mut o {
            *c = it.next()?.parse().ok()?;
        }
        o.iter().all(|v| v.is_finite()).then_some(o)
    }

    /// The brush model this entity uses (`"model" "*N"`), if any.
    pub fn model_index(&self) -> Option<usize> {
        self.get("model")?.strip_prefix('*')?.parse().ok()
    }
}

/// Parses the entity lump text.
pub fn parse_entities(bytes: &[u8]) -> Result<Vec<Entity>, BspError> {
    let text = String::from_utf8_lossy(bytes);
    let text = text.trim_end_matches('\0');
    let mut entities = Vec::new();
    let mut chars = text.char_indices().peekable();
    let mut current: Option<Entity> = None;
    let mut pending_key: Option<String> = None;
    let line_of = |pos: usize| text[..pos].bytes().filter(|&b| b == b'\n').count() + 1;
    let err = |pos: usize, what: &str| BspError::Malformed {
        lump: "entities",
        reason: format!("{what} at line {}", line_of(pos)),
    };
    while let Some((pos, c)) = chars.next() {
        match c {
            '{' => {
                if current.is_some() {
                    return Err(err(pos, "'{' inside an entity"));
                }
                current = Some(Entity::default());
            }
            '}' => {
                let Some(e) = current.take() else {
                    return Err(err(pos, "'}' without an open entity"));
                };
                if pending_key.is_some() {
                    return Err(err(pos, "key without a value"));
                }
                entities.push(e);
            }
            '"' => {
                let Some(e) = current.as_mut() else {
                    return Err(err(pos, "string outside an entity"));
                };
                let mut s = String::new();
                let mut closed = false;
                for (_, c) in chars.by_ref() {
                    if c == '"' {
                        closed = true;
                        break;
                    }
                    s.push(c);
                }
                if !closed {
                    return Err(err(pos, "unterminated string"));
                }
                match pending_key.take() {
                    None => pending_key = Some(s),
                    Some(k) => e.pairs.push((k, s)),
                }
            }
            c if c.is_whitespace() || c == '\0' => {}
            _ => return Err(err(pos, &format!("unexpected character {c:?}"))),
        }
    }
    if current.is_some() {
        return Err(BspError::Malformed {
            lump: "entities",
            reason: "the last entity is not closed".into(),
        });
    }
    Ok(entities)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_blocks_and_keys() {
        let text = b"{\n\"classname\" \"worldspawn\"\n\"wad\" \"a.wad;b.wad\"\n}\n{\n\"classname\" \"info_player_start\"\n\"origin\" \"1 -2 3.5\"\n}\n{\n\"model\" \"*3\"\n}\n\0";
        let e = parse_entities(text).unwrap();
        assert_eq!(e.len(), 3);
        assert_eq!(e[0].classname(), "worldspawn");
        assert_eq!(e[0].get("wad"), Some("a.wad;b.wad"));
        assert_eq!(e[1].origin(), Some([1.0, -2.0, 3.5]));
        assert_eq!(e[2].model_index(), Some(3));
        assert_eq!(e[2].classname(), "");
    }

    #[test]
    fn rejects_broken_text_with_a_line_number() {
        for bad in [
            &b"{ \"a\" \"b\" "[..],
            b"}",
            b"{ \"a\" \"b }",
            b"{ \"a\" }",
            b"{ x }",
        ] {
            let msg = parse_entities(bad).unwrap_err().to_string();
            assert!(msg.starts_with("lump entities:"), "{msg}");
        }
        let msg = parse_entities(b"{\n\"a\" \"b\"\n{")
            .unwrap_err()
            .to_string();
        assert!(msg.contains("line 3"), "{msg}");
    }
}
