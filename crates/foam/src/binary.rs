//! The binary layout of OpenFOAM's contiguous lists, described by the header's `arch` entry,
//! e.g. `arch "LSB;label=32;scalar=64";` (little-endian, 32-bit labels, double precision).

/// Byte order and sizes of labels and scalars in binary lists.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Arch {
    /// True for little-endian (`LSB`), false for big-endian (`MSB`).
    pub little_endian: bool,
    /// Bytes per label: 4 or 8.
    pub label_bytes: usize,
    /// Bytes per scalar: 4 or 8.
    pub scalar_bytes: usize,
}

impl Default for Arch {
    /// `LSB;label=32;scalar=64`, what Debian's OpenFOAM v1912 writes.
    fn default() -> Self {
        Arch {
            little_endian: true,
            label_bytes: 4,
            scalar_bytes: 8,
        }
    }
}

impl Arch {
    /// Parses an `arch` string such as `LSB;label=32;scalar=64`. Missing parts keep their
    /// default; an unknown size is an error.
    pub fn parse(s: &str) -> Result<Arch, String> {
        let mut a = Arch::default();
        for part in s.split(';').map(str::trim).filter(|p| !p.is_empty()) {
            match part {
                "LSB" => a.little_endian = true,
                "MSB" => a.little_endian = false,
                _ => {
                    let (k, v) = part.split_once('=').ok_or_else(|| {
                        format!("arch part `{part}` is not LSB, MSB or key=value")
                    })?;
                    let bytes = match v {
                        "32" => 4,
                        "64" => 8,
                        _ => return Err(format!("arch `{part}`: size must be 32 or 64")),
                    };
                    match k {
                        "label" => a.label_bytes = bytes,
                        "scalar" => a.scalar_bytes = bytes,
                        _ => return Err(format!("arch `{part}`: unknown key `{k}`")),
                    }
                }
            }
        }
        Ok(a)
    }

    /// The `arch` string for this layout.
    pub fn to_arch_string(&self) -> String {
        format!(
            "{};label={};scalar={}",
            if self.little_endian { "LSB" } else { "MSB" },
            self.label_bytes * 8,
            self.scalar_bytes * 8
        )
    }

    /// Decodes `bytes` (a whole number of scalars) into f64 values.
    pub fn decode_scalars(&self, bytes: &[u8], out: &mut Vec<f64>) {
        let le = self.little_endian;
        if self.scalar_bytes == 8 {
            out.extend(bytes.chunks_exact(8).map(|c| {
                let a: [u8; 8] = c.try_into().unwrap();
                if le {
                    f64::from_le_bytes(a)
                } else {
                    f64::from_be_bytes(a)
                }
            }));
        } else {
            out.extend(bytes.chunks_exact(4).map(|c| {
                let a: [u8; 4] = c.try_into().unwrap();
                f64::from(if le {
                    f32::from_le_bytes(a)
                } else {
                    f32::from_be_bytes(a)
                })
            }));
        }
    }

    /// Decodes `bytes` (a whole number of labels) into i64 values.
    pub fn decode_labels(&self, bytes: &[u8], out: &mut Vec<i64>) {
        let le = self.little_endian;
        if self.label_bytes == 4 {
            out.extend(bytes.chunks_exact(4).map(|c| {
                let a: [u8; 4] = c.try_into().unwrap();
                i64::from(if le {
                    i32::from_le_bytes(a)
                } else {
                    i32::from_be_bytes(a)
                })
            }));
        } else {
            out.extend(bytes.chunks_exact(8).map(|c| {
                let a: [u8; 8] = c.try_into().unwrap();
                if le {
                    i64::from_le_bytes(a)
                } else {
                    i64::from_be_bytes(a)
                }
            }));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_debian_default_and_variants() {
        assert_eq!(
            Arch::parse("LSB;label=32;scalar=64").unwrap(),
            Arch::default()
        );
        let a = Arch::parse("MSB;label=64;scalar=32").unwrap();
        assert!(!a.little_endian);
        assert_eq!((a.label_bytes, a.scalar_bytes), (8, 4));
        assert_eq!(a.to_arch_string(), "MSB;label=64;scalar=32");
        assert!(Arch::parse("LSB;label=16").is_err());
        assert!(Arch::parse("LSB;colour=32").is_err());
    }

    #[test]
    fn decodes_both_byte_orders() {
        let mut out = Vec::new();
        let a = Arch::parse("MSB;label=32;scalar=64").unwrap();
        a.decode_scalars(&1.5f64.to_be_bytes(), &mut out);
        assert_eq!(out, [1.5]);
        let mut l = Vec::new();
        Arch::default().decode_labels(&(-7i32).to_le_bytes(), &mut l);
        assert_eq!(l, [-7]);
    }
}
