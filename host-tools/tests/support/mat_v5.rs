//! A minimal MATLAB v5 (`save -v7` without compression) writer for tests:
//! real double matrices only, little-endian. Layout from MathWorks' "MAT-File
//! Format" (128-byte header, then one miMATRIX element per variable holding
//! array flags, dimensions, name and real part, each padded to 8 bytes).

const MI_INT8: u32 = 1;
const MI_INT32: u32 = 5;
const MI_UINT32: u32 = 6;
const MI_DOUBLE: u32 = 9;
const MI_MATRIX: u32 = 14;
const MX_DOUBLE_CLASS: u32 = 6;

fn element(out: &mut Vec<u8>, ty: u32, data: &[u8]) {
    out.extend_from_slice(&ty.to_le_bytes());
    out.extend_from_slice(&(data.len() as u32).to_le_bytes());
    out.extend_from_slice(data);
    while !out.len().is_multiple_of(8) {
        out.push(0);
    }
}

/// A .mat file holding each `(name, rows, cols, column-major values)`.
pub fn mat_v5(vars: &[(&str, usize, usize, &[f64])]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut text = b"MATLAB 5.0 MAT-file, written by the mre tests".to_vec();
    text.resize(116, b' ');
    out.extend_from_slice(&text);
    out.extend_from_slice(&[0; 8]); // no subsystem data
    out.extend_from_slice(&0x0100u16.to_le_bytes());
    out.extend_from_slice(b"IM");
    for (name, rows, cols, values) in vars {
        assert_eq!(rows * cols, values.len());
        let mut body = Vec::new();
        let mut flags = MX_DOUBLE_CLASS.to_le_bytes().to_vec();
        flags.extend_from_slice(&0u32.to_le_bytes());
        element(&mut body, MI_UINT32, &flags);
        let mut dims = (*rows as i32).to_le_bytes().to_vec();
        dims.extend_from_slice(&(*cols as i32).to_le_bytes());
        element(&mut body, MI_INT32, &dims);
        element(&mut body, MI_INT8, name.as_bytes());
        let real: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        element(&mut body, MI_DOUBLE, &real);
        element(&mut out, MI_MATRIX, &body);
    }
    out
}

/// The first bytes of a MATLAB v7.3 file: a 512-byte header block (version
/// 0x0200) followed by the HDF5 signature.
pub fn mat_v73_header() -> Vec<u8> {
    let mut out =
        b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Mon Jan  1 00:00:00 2024 HDF5 schema 1.00 .".to_vec();
    out.resize(116, b' ');
    out.extend_from_slice(&[0; 8]);
    out.extend_from_slice(&0x0200u16.to_le_bytes());
    out.extend_from_slice(b"IM");
    out.resize(512, 0);
    out.extend_from_slice(b"\x89HDF\r\n\x1a\n");
    out.resize(1024, 0);
    out
}
