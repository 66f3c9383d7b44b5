//! The Pareto front of (cost, error) points: those no other point beats on both.

/// For each point `(cost, error)`, whether it is on the Pareto front: no other point has
/// cost ≤ and error ≤ with one of them strictly less. Equal points are all on the front.
pub fn front(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(c, e)| {
            !points
                .iter()
                .any(|&(c2, e2)| c2 <= c && e2 <= e && (c2 < c || e2 < e))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::front;

    #[test]
    fn a_dominated_point_is_off_the_front() {
        // (3, 3) is beaten by (2, 2); (1, 5), (2, 2) and (4, 0) each win somewhere.
        let p = [(1.0, 5.0), (2.0, 2.0), (3.0, 3.0), (4.0, 0.0)];
        assert_eq!(front(&p), [true, true, false, true]);
        // Same cost, larger error: dominated; equal points both stay.
        assert_eq!(front(&[(1.0, 1.0), (1.0, 2.0)]), [true, false]);
        assert_eq!(front(&[(1.0, 1.0), (1.0, 1.0)]), [true, true]);
    }
}
