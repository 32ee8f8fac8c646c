//! `R(q)` written out, the tests' independent oracle for rigid3's own (shared by
//! `tests/common` and the lab's tests).

/// The rotation matrix `R(q)` of a unit quaternion `(w, x, y, z)`, written out (not
/// rigid3's: an independent oracle).
pub fn rotation(q: [f64; 4]) -> [[f64; 3]; 3] {
    let [w, x, y, z] = q;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}
