//! NumPy's `.npy` array format, version 1.0, for the `.npz` export: a magic string, a header
//! dictionary (`descr`, `fortran_order`, `shape`) padded to 64 bytes, then the data in C
//! order. Hand-written because the format is one page of NumPy's documentation and the
//! crates that write it (ndarray-npy, npyz) would bring a second array type for three
//! matrices; the `.npz` container is a plain zip archive (the `zip` crate).

use std::io::Write;

/// One array: its dtype and shape, and its data in C order.
pub enum Array<'a> {
    /// Little-endian `f64` (`<f8`).
    Float { shape: Vec<usize>, data: &'a [f64] },
    /// Unicode strings (`<U{width}`, UTF-32 code units), one per element.
    Text {
        shape: Vec<usize>,
        data: &'a [String],
    },
}

/// The character width of a text array's cells: its longest string, at least 1.
fn text_width(data: &[String]) -> usize {
    data.iter()
        .map(|s| s.chars().count())
        .max()
        .unwrap_or(0)
        .max(1)
}

/// Writes `array` as a `.npy` file.
pub fn write(w: &mut dyn Write, array: &Array) -> std::io::Result<()> {
    let (descr, shape) = match array {
        Array::Float { shape, .. } => ("<f8".to_string(), shape),
        Array::Text { shape, data } => {
            let width = text_width(data);
            (format!("<U{width}"), shape)
        }
    };
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let shape_text = match dims.len() {
        0 => "()".to_string(),
        1 => format!("({},)", dims[0]),
        _ => format!("({})", dims.join(", ")),
    };
    let mut header =
        format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape_text}, }}");
    // magic (6) + version (2) + length (2) + header + newline: a multiple of 64
    let total = 10 + header.len() + 1;
    header.push_str(&" ".repeat((64 - total % 64) % 64));
    header.push('\n');
    w.write_all(b"\x93NUMPY\x01\x00")?;
    w.write_all(&(header.len() as u16).to_le_bytes())?;
    w.write_all(header.as_bytes())?;
    match array {
        Array::Float { data, .. } => {
            for v in *data {
                w.write_all(&v.to_le_bytes())?;
            }
        }
        Array::Text { data, .. } => {
            let width = text_width(data);
            for s in *data {
                let mut n = 0;
                for c in s.chars() {
                    w.write_all(&(c as u32).to_le_bytes())?;
                    n += 1;
                }
                for _ in n..width {
                    w.write_all(&0u32.to_le_bytes())?;
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headers_are_padded_to_64_bytes_and_data_follows_in_c_order() {
        let mut out = Vec::new();
        let data = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        write(
            &mut out,
            &Array::Float {
                shape: vec![2, 3],
                data: &data,
            },
        )
        .unwrap();
        let header_len = u16::from_le_bytes([out[8], out[9]]) as usize;
        assert_eq!((10 + header_len) % 64, 0);
        let header = std::str::from_utf8(&out[10..10 + header_len]).unwrap();
        assert!(header.starts_with("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }"));
        assert!(header.ends_with('\n'));
        assert_eq!(out.len(), 10 + header_len + 6 * 8);
        assert_eq!(
            f64::from_le_bytes(out[10 + header_len + 8..][..8].try_into().unwrap()),
            2.0
        );
    }
}
