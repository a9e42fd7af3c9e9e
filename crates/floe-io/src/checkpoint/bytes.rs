//! The checkpoint's words: little-endian integers, every `f64` as its IEEE
//! bits, a vector as its length (u64) then its elements.

use floe_dem::Vec2;

/// Errors of reading: what is wrong, at which byte.
pub(super) type ReadResult<T> = Result<T, String>;

/// The payload being written and the law-state slots written per
/// friction state.
pub(super) struct Writer {
    pub bytes: Vec<u8>,
    pub law_state_slots: usize,
}

impl Writer {
    pub fn u8(&mut self, v: u8) {
        self.bytes.push(v);
    }
    pub fn u32(&mut self, v: u32) {
        self.bytes.extend_from_slice(&v.to_le_bytes());
    }
    pub fn u64(&mut self, v: u64) {
        self.bytes.extend_from_slice(&v.to_le_bytes());
    }
    pub fn f64(&mut self, v: f64) {
        self.u64(v.to_bits());
    }
    pub fn v2(&mut self, v: Vec2) {
        self.f64(v.x);
        self.f64(v.y);
    }
    pub fn len(&mut self, n: usize) {
        self.u64(n as u64);
    }
    pub fn f64s(&mut self, v: &[f64]) {
        self.len(v.len());
        v.iter().for_each(|&x| self.f64(x));
    }
    pub fn v2s(&mut self, v: &[Vec2]) {
        self.len(v.len());
        v.iter().for_each(|&x| self.v2(x));
    }
    pub fn str(&mut self, s: &str) {
        self.len(s.len());
        self.bytes.extend_from_slice(s.as_bytes());
    }
}

/// The payload being read and the format version it follows.
pub(super) struct Reader<'a> {
    pub buf: &'a [u8],
    pub pos: usize,
    pub version: u32,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> ReadResult<&'a [u8]> {
        let end = self
            .pos
            .checked_add(n)
            .filter(|&e| e <= self.buf.len())
            .ok_or_else(|| format!("truncated at byte {} (wanted {n} more)", self.pos))?;
        let s = &self.buf[self.pos..end];
        self.pos = end;
        Ok(s)
    }
    pub fn u8(&mut self) -> ReadResult<u8> {
        Ok(self.take(1)?[0])
    }
    pub fn u32(&mut self) -> ReadResult<u32> {
        let mut b = [0; 4];
        b.copy_from_slice(self.take(4)?);
        Ok(u32::from_le_bytes(b))
    }
    pub fn u64(&mut self) -> ReadResult<u64> {
        let mut b = [0; 8];
        b.copy_from_slice(self.take(8)?);
        Ok(u64::from_le_bytes(b))
    }
    pub fn f64(&mut self) -> ReadResult<f64> {
        Ok(f64::from_bits(self.u64()?))
    }
    pub fn v2(&mut self) -> ReadResult<Vec2> {
        Ok(Vec2::new(self.f64()?, self.f64()?))
    }
    /// A length prefix, checked against the bytes left (each element is at
    /// least `min_elem` bytes), so a corrupt length cannot allocate wildly.
    fn len(&mut self, min_elem: usize) -> ReadResult<usize> {
        let n = self.u64()?;
        let left = (self.buf.len() - self.pos) as u64;
        if n.saturating_mul(min_elem as u64) > left {
            return Err(format!(
                "length {n} at byte {} exceeds the {left} bytes left",
                self.pos - 8
            ));
        }
        Ok(n as usize)
    }
    /// A vector of elements of at least `min_elem` bytes each, read by `f`.
    pub fn vec<T>(
        &mut self,
        min_elem: usize,
        mut f: impl FnMut(&mut Self) -> ReadResult<T>,
    ) -> ReadResult<Vec<T>> {
        let n = self.len(min_elem)?;
        let mut v = Vec::with_capacity(n);
        for _ in 0..n {
            v.push(f(self)?);
        }
        Ok(v)
    }
    pub fn f64s(&mut self) -> ReadResult<Vec<f64>> {
        self.vec(8, Self::f64)
    }
    pub fn v2s(&mut self) -> ReadResult<Vec<Vec2>> {
        self.vec(16, Self::v2)
    }
    pub fn str(&mut self) -> ReadResult<String> {
        let n = self.len(1)?;
        String::from_utf8(self.take(n)?.to_vec()).map_err(|_| "a series name is not UTF-8".into())
    }
    /// Whether every byte of the payload was read.
    pub fn unread(&self) -> usize {
        self.buf.len() - self.pos
    }
}
