//! A bounds-checked little-endian reader over the file's bytes: every read names what it
//! was reading, so a truncated file gives an error saying where and what.

use crate::Error;

pub(crate) struct Cursor<'a> {
    bytes: &'a [u8],
    pub(crate) at: usize,
}

impl<'a> Cursor<'a> {
    pub(crate) fn new(bytes: &'a [u8], at: usize) -> Cursor<'a> {
        Cursor { bytes, at }
    }

    pub(crate) fn take(&mut self, n: usize, what: &'static str) -> Result<&'a [u8], Error> {
        match self.at.checked_add(n) {
            Some(end) if end <= self.bytes.len() => {
                let s = &self.bytes[self.at..end];
                self.at = end;
                Ok(s)
            }
            _ => Err(Error::Truncated {
                what,
                at: self.at,
                len: self.bytes.len(),
            }),
        }
    }

    pub(crate) fn skip(&mut self, n: usize, what: &'static str) -> Result<(), Error> {
        self.take(n, what).map(|_| ())
    }

    fn array<const N: usize>(&mut self, what: &'static str) -> Result<[u8; N], Error> {
        let mut a = [0u8; N];
        a.copy_from_slice(self.take(N, what)?);
        Ok(a)
    }

    pub(crate) fn u8(&mut self, what: &'static str) -> Result<u8, Error> {
        Ok(self.take(1, what)?[0])
    }

    pub(crate) fn i32(&mut self, what: &'static str) -> Result<i32, Error> {
        Ok(i32::from_le_bytes(self.array(what)?))
    }

    pub(crate) fn u32(&mut self, what: &'static str) -> Result<u32, Error> {
        Ok(u32::from_le_bytes(self.array(what)?))
    }

    /// A float as stored; non-finite values are kept (the player's motion rejects them
    /// where it uses them, other fields are never read as numbers).
    pub(crate) fn f32(&mut self, what: &'static str) -> Result<f32, Error> {
        Ok(f32::from_le_bytes(self.array(what)?))
    }

    pub(crate) fn vec3(&mut self, what: &'static str) -> Result<[f32; 3], Error> {
        Ok([self.f32(what)?, self.f32(what)?, self.f32(what)?])
    }

    /// A fixed-size, NUL-padded string field.
    pub(crate) fn string(&mut self, n: usize, what: &'static str) -> Result<String, Error> {
        let raw = self.take(n, what)?;
        let s = raw.split(|&c| c == 0).next().unwrap_or(&[]);
        Ok(String::from_utf8_lossy(s).into_owned())
    }

    /// A length field that must lie in `0..=max` and fit in the rest of the file.
    pub(crate) fn length(&mut self, max: usize, what: &'static str) -> Result<usize, Error> {
        let at = self.at;
        let n = self.i32(what)?;
        if n < 0 || n as usize > max {
            return Err(Error::BadLength {
                what,
                value: n as i64,
                max,
                at,
            });
        }
        Ok(n as usize)
    }
}
