//! Seam unwrapping of cylindrical and spherical u along one primitive.

use geode_geo::glam::Vec3;

/// Makes u continuous along one primitive's vertices: `uv[i].x` is u,
/// `uv[i].z` is 1 for a vertex on the axis (its u is meaningless) and 0
/// otherwise. Each vertex off the axis has its u moved by whole turns to
/// lie within half a turn of the previous such vertex; vertices on the
/// axis then take the mean u of the others (all keep u = 0 when none is
/// off the axis). The z flags are left for the caller to clear.
pub(super) fn unwrap_prim(uv: &mut [Vec3]) {
    let mut previous: Option<f32> = None;
    let mut sum = 0.0f64;
    let mut count = 0usize;
    for t in uv.iter_mut().filter(|t| t.z == 0.0) {
        if let Some(prev) = previous {
            t.x -= (t.x - prev).round();
        }
        previous = Some(t.x);
        sum += t.x as f64;
        count += 1;
    }
    if count < uv.len() {
        let mean = if count == 0 {
            0.0
        } else {
            (sum / count as f64) as f32
        };
        for t in uv.iter_mut().filter(|t| t.z != 0.0) {
            t.x = mean;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn us(uv: &[Vec3]) -> Vec<f32> {
        uv.iter().map(|t| t.x).collect()
    }

    #[test]
    fn a_polygon_across_the_seam_is_continuous() {
        let mut uv = [0.95, 0.02, 0.04, 0.97].map(|u| Vec3::new(u, 0.0, 0.0));
        unwrap_prim(&mut uv);
        let u = us(&uv);
        assert!(
            (u[1] - 1.02).abs() < 1e-6 && (u[2] - 1.04).abs() < 1e-6,
            "{u:?}"
        );
        assert_eq!(u[0], 0.95);
        assert_eq!(u[3], 0.97);
    }

    #[test]
    fn a_pole_takes_the_mean_of_the_others() {
        let mut uv = [
            Vec3::new(0.0, 1.0, 1.0),
            Vec3::new(0.98, 0.9, 0.0),
            Vec3::new(0.02, 0.9, 0.0),
        ];
        unwrap_prim(&mut uv);
        assert!((uv[0].x - 1.0).abs() < 1e-6, "{:?}", us(&uv));
        assert!((uv[2].x - 1.02).abs() < 1e-6);
    }

    #[test]
    fn all_on_the_axis_stays_at_zero() {
        let mut uv = [Vec3::new(0.3, 0.0, 1.0), Vec3::new(0.7, 1.0, 1.0)];
        unwrap_prim(&mut uv);
        assert_eq!(us(&uv), vec![0.0, 0.0]);
    }
}
