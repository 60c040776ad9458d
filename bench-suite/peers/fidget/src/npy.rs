//! A NumPy `.npy` (format 1.0) writer for row-major 2-D `u8` and little-endian `f32`
//! arrays of shape `(rows, cols)`: the hit mask and the depth map, small enough not to
//! need a crate.

use std::io::Write;

/// The bytes of a `.npy` file of a `(rows, cols)` array of dtype `descr` whose
/// row-major element bytes are `data`.
fn encode(descr: &str, rows: usize, cols: usize, data: &[u8]) -> Vec<u8> {
    let mut header =
        format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': ({rows}, {cols}), }}");
    // Magic (6) + version (2) + header length (2) + header, padded with spaces and
    // ended by '\n' to a multiple of 64 bytes.
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat(unpadded.next_multiple_of(64) - unpadded));
    header.push('\n');
    let mut out = Vec::with_capacity(10 + header.len() + data.len());
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    out.extend_from_slice(data);
    out
}

/// The bytes of a `.npy` file holding `data` as a `(rows, cols)` `u8` array.
///
/// # Panics
/// If `data.len() != rows * cols`.
pub fn encode_u8(rows: usize, cols: usize, data: &[u8]) -> Vec<u8> {
    assert_eq!(data.len(), rows * cols, "array size");
    encode("|u1", rows, cols, data)
}

/// The bytes of a `.npy` file holding `data` as a `(rows, cols)` `<f4` array.
///
/// # Panics
/// If `data.len() != rows * cols`.
pub fn encode_f32(rows: usize, cols: usize, data: &[f32]) -> Vec<u8> {
    assert_eq!(data.len(), rows * cols, "array size");
    let bytes: Vec<u8> = data.iter().flat_map(|v| v.to_le_bytes()).collect();
    encode("<f4", rows, cols, &bytes)
}

/// Writes `bytes` (from [`encode_u8`] or [`encode_f32`]) to `path`.
pub fn write(path: &std::path::Path, bytes: &[u8]) -> std::io::Result<()> {
    std::fs::File::create(path)?.write_all(bytes)
}

#[cfg(test)]
mod tests {
    use super::{encode_f32, encode_u8};

    #[test]
    fn header_is_aligned_and_names_the_shape() {
        let data = [0u8, 1, 1, 0, 1, 0];
        let b = encode_u8(2, 3, &data);
        assert_eq!(&b[..8], b"\x93NUMPY\x01\x00");
        let hlen = u16::from_le_bytes([b[8], b[9]]) as usize;
        assert_eq!((10 + hlen) % 64, 0);
        let header = std::str::from_utf8(&b[10..10 + hlen]).unwrap();
        assert!(header.contains("'shape': (2, 3)"), "{header}");
        assert!(header.ends_with('\n'));
        assert_eq!(&b[10 + hlen..], &data);
    }

    #[test]
    fn f32_data_is_little_endian() {
        let b = encode_f32(1, 2, &[1.0, f32::INFINITY]);
        let hlen = u16::from_le_bytes([b[8], b[9]]) as usize;
        assert!(std::str::from_utf8(&b[10..10 + hlen])
            .unwrap()
            .contains("'<f4'"));
        assert_eq!(&b[10 + hlen..], &[0, 0, 0x80, 0x3f, 0, 0, 0x80, 0x7f]);
    }
}
