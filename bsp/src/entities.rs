//! The entity lump: a text list of `{ "key" "value" ... }` blocks.
//!
//! Read as the engines read it (Quake's and GoldSrc's `COM_Parse` feeding
//! `ED_ParseEdict`): a token is a quoted string, a brace, or a bare word running to the
//! next space, brace or quote; `//` starts a comment. So an unquoted key or value, a
//! quote missing at the end of the lump, stray bytes or a missing final NUL do not stop
//! a map the game loads. Nor does an entity left open at the end of the text: the
//! engine's parser reads to the end and keeps what it read (a key left without its
//! value there is dropped). What the engine itself refuses is refused, with the line:
//! a block that does not open with `{`, a `{` inside an entity, a key followed by a
//! brace instead of its value.
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

/// One token of the entity text and the byte offset where it starts.
#[derive(Debug, PartialEq)]
enum Token {
    Open,
    Close,
    Word(String),
}

/// `COM_Parse`: the next token after `*pos`, or `None` at the end of the text.
fn next_token(text: &str, pos: &mut usize) -> Option<(usize, Token)> {
    let bytes = text.as_bytes();
    loop {
        while *pos < bytes.len() && (bytes[*pos].is_ascii_whitespace() || bytes[*pos] == 0) {
            *pos += 1;
        }
        if bytes[*pos..].starts_with(b"//") {
            while *pos < bytes.len() && bytes[*pos] != b'\n' {
                *pos += 1;
            }
            continue;
        }
        break;
    }
    let start = *pos;
    match *bytes.get(start)? {
        b'{' => {
            *pos += 1;
            Some((start, Token::Open))
        }
        b'}' => {
            *pos += 1;
            Some((start, Token::Close))
        }
        b'"' => {
            // Up to the closing quote, or the end of the text when it is missing.
            let end = text[start + 1..]
                .find('"')
                .map_or(bytes.len(), |i| start + 1 + i);
            *pos = (end + 1).min(bytes.len());
            Some((start, Token::Word(text[start + 1..end].to_string())))
        }
        _ => {
            let end = text[start..]
                .find(|c: char| c.is_ascii_whitespace() || matches!(c, '{' | '}' | '"' | '\0'))
                .map_or(bytes.len(), |i| start + i);
            *pos = end;
            Some((start, Token::Word(text[start..end].to_string())))
        }
    }
}

/// Parses the entity lump text.
pub fn parse_entities(bytes: &[u8]) -> Result<Vec<Entity>, BspError> {
    let text = String::from_utf8_lossy(bytes);
    let text = text.as_ref();
    let line_of = |pos: usize| text[..pos].bytes().filter(|&b| b == b'\n').count() + 1;
    let err = |pos: usize, what: &str| BspError::Malformed {
        lump: "entities",
        reason: format!("{what} at line {}", line_of(pos)),
    };
    let mut entities = Vec::new();
    let mut pos = 0;
    while let Some((at, token)) = next_token(text, &mut pos) {
        if token != Token::Open {
            return Err(err(at, "expected '{' to open an entity"));
        }
        let mut entity = Entity::default();
        // The end of the text ends an entity left open.
        while let Some((at, key)) = next_token(text, &mut pos) {
            let key = match key {
                Token::Close => break,
                Token::Open => return Err(err(at, "'{' inside an entity")),
                Token::Word(k) => k,
            };
            match next_token(text, &mut pos) {
                Some((_, Token::Word(value))) => entity.pairs.push((key, value)),
                Some((at, _)) => return Err(err(at, "key without a value")),
                None => break,
            }
        }
        entities.push(entity);
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
        for bad in [&b"}"[..], b"{ \"a\" }", b"{ x }", b"x { }"] {
            let msg = parse_entities(bad).unwrap_err().to_string();
            assert!(msg.starts_with("lump entities:"), "{msg}");
        }
        let msg = parse_entities(b"{\n\"a\" \"b\"\n{")
            .unwrap_err()
            .to_string();
        assert!(msg.contains("line 3"), "{msg}");
    }

    /// The engine reads an entity left open at the end of the text as ended there.
    #[test]
    fn an_unclosed_last_entity_ends_at_the_end_of_the_text() {
        for (text, pairs) in [
            (
                &b"{ \"classname\" \"worldspawn\" } { \"classname\" \"light\" "[..],
                1,
            ),
            (
                b"{ \"classname\" \"worldspawn\" } { \"classname\" \"light\" \"origin",
                1,
            ),
            (
                b"{ \"classname\" \"worldspawn\" } { \"classname\" \"light\" \"origin\" \"1 2",
                2,
            ),
        ] {
            let e = parse_entities(text).unwrap();
            assert_eq!(e.len(), 2);
            assert_eq!(e[1].classname(), "light");
            assert_eq!(e[1].pairs.len(), pairs, "{}", String::from_utf8_lossy(text));
        }
    }

    /// What the game's `COM_Parse` reads must read: bare words, comments, a word
    /// glued to a string.
    #[test]
    fn reads_what_the_engine_reads() {
        let text = b"// made by hand\n{\n\"classname\" \"worldspawn\"\nmapversion 220\n}\n{\n\"classname\" \"light\"m 5\n\"origin\" \"1 2 3\"}";
        let e = parse_entities(text).unwrap();
        assert_eq!(e.len(), 2);
        assert_eq!(e[0].get("mapversion"), Some("220"));
        assert_eq!(e[1].classname(), "light");
        assert_eq!(e[1].get("m"), Some("5"));
        assert_eq!(e[1].origin(), Some([1.0, 2.0, 3.0]));
    }
}
