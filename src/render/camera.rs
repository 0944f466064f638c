//! The orthographic camera: a view direction named relative to the scene's up axis, framed on
//! a bounding box, and the map from world points to view coordinates.

use glam::DVec3;

/// Where the camera stands, relative to the up axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// Facing the scene with `up` vertical (the drums' axis is the line of sight when up is y).
    Front,
    Back,
    /// From the right of the front view.
    Side,
    /// Looking down the up axis.
    Top,
    /// From the front, right and above at equal angles.
    Iso,
}

impl View {
    pub const NAMES: &'static str = "front, back, side, top, iso";

    pub fn parse(name: &str) -> Result<View, String> {
        Ok(match name {
            "front" => View::Front,
            "back" => View::Back,
            "side" => View::Side,
            "top" => View::Top,
            "iso" => View::Iso,
            _ => return Err(format!("--view {name}: unknown view (valid: {})", View::NAMES)),
        })
    }
}

/// The world's up axis: 0, 1, 2 for x, y, z.
pub fn parse_axis(name: &str) -> Result<usize, String> {
    match name {
        "x" => Ok(0),
        "y" => Ok(1),
        "z" => Ok(2),
        _ => Err(format!("--up {name}: unknown axis (valid: x, y, z)")),
    }
}

/// An orthographic camera: `right`, `up`, `back` (towards the viewer) orthonormal and
/// right-handed; the frame shows `centre ± half_width·right ± half_height·up`, and depths
/// within `centre ± depth·back`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub right: DVec3,
    pub up: DVec3,
    pub back: DVec3,
    pub centre: DVec3,
    pub half_width: f64,
    pub half_height: f64,
    pub depth: f64,
}

impl Camera {
    /// The camera's axes for `view` with world axis `up_axis` vertical.
    pub fn axes(view: View, up_axis: usize) -> (DVec3, DVec3, DVec3) {
        // The front view's right, up and back for each up axis (right × up = back).
        let (r, u, b) = match up_axis {
            0 => (DVec3::Y, DVec3::X, DVec3::NEG_Z),
            1 => (DVec3::X, DVec3::Y, DVec3::Z),
            _ => (DVec3::X, DVec3::Z, DVec3::NEG_Y),
        };
        match view {
            View::Front => (r, u, b),
            View::Back => (-r, u, -b),
            View::Side => (-b, u, r),
            View::Top => (r, -b, u),
            View::Iso => {
                let back = (r + u + b).normalize();
                let up = (u - back * u.dot(back)).normalize();
                (up.cross(back), up, back)
            }
        }
    }

    /// The camera for `view` that shows the box `[min, max]` whole with a 4 % margin, in a
    /// frame of width/height `aspect`.
    pub fn framing(view: View, up_axis: usize, min: DVec3, max: DVec3, aspect: f64) -> Camera {
        let (right, up, back) = Camera::axes(view, up_axis);
        let corners = (0..8).map(|k| DVec3::new([min.x, max.x][k & 1], [min.y, max.y][(k >> 1) & 1], [min.z, max.z][(k >> 2) & 1]));
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for c in corners {
            let v = DVec3::new(c.dot(right), c.dot(up), c.dot(back));
            (lo, hi) = (lo.min(v), hi.max(v));
        }
        let mid = 0.5 * (lo + hi);
        let half = (0.5 * (hi - lo) * 1.04).max(DVec3::splat(1e-9 * (hi - lo).max_element().max(1e-300)));
        let (mut half_width, mut half_height) = (half.x, half.y);
        if half_width < half_height * aspect {
            half_width = half_height * aspect;
        } else {
            half_height = half_width / aspect;
        }
        Camera { right, up, back, centre: right * mid.x + up * mid.y + back * mid.z, half_width, half_height, depth: half.z }
    }

    /// `p` in view coordinates: right, up, and towards the viewer, from the centre.
    pub fn to_view(&self, p: DVec3) -> DVec3 {
        let d = p - self.centre;
        DVec3::new(d.dot(self.right), d.dot(self.up), d.dot(self.back))
    }

    /// The pixel (x right, y down, continuous; pixel k spans [k, k + 1)) where `p` lands.
    pub fn pixel(&self, p: DVec3, width: u32, height: u32) -> (f64, f64) {
        let v = self.to_view(p);
        ((v.x / self.half_width + 1.0) * 0.5 * width as f64, (1.0 - v.y / self.half_height) * 0.5 * height as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_view_is_a_right_handed_orthonormal_frame_with_the_camera_where_named() {
        for up_axis in 0..3 {
            let world_up = DVec3::AXES[up_axis];
            for view in [View::Front, View::Back, View::Side, View::Top, View::Iso] {
                let (r, u, b) = Camera::axes(view, up_axis);
                assert!((r.cross(u) - b).length() < 1e-12, "{view:?} up {up_axis}");
                assert!((r.length() - 1.0).abs() < 1e-12 && (u.length() - 1.0).abs() < 1e-12);
                match view {
                    View::Top => assert_eq!(b, world_up),
                    View::Iso => assert!((b.dot(world_up) - 1.0 / 3f64.sqrt()).abs() < 1e-12 && u.dot(world_up) > 0.0),
                    _ => assert_eq!(u, world_up),
                }
            }
        }
        // With y up the front view looks down the z axis from +z (a drum's end-on view).
        assert_eq!(Camera::axes(View::Front, 1).2, DVec3::Z);
    }

    #[test]
    fn the_frame_holds_the_box_and_keeps_the_aspect() {
        let (min, max) = (DVec3::new(-1.0, 0.0, 2.0), DVec3::new(3.0, 1.0, 4.0));
        let c = Camera::framing(View::Front, 2, min, max, 2.0);
        // Front with z up: x across (width 4), z up (height 2): the box fits 2:1 with the margin.
        assert!((c.half_width - 2.08).abs() < 1e-12 && (c.half_height - 1.04).abs() < 1e-12, "{c:?}");
        assert_eq!(c.pixel(DVec3::new(1.0, 0.5, 3.0), 200, 100), (100.0, 50.0));
        let (x, y) = c.pixel(DVec3::new(3.0, 0.0, 4.0), 200, 100);
        assert!((x - 100.0 * (1.0 + 2.0 / 2.08)).abs() < 1e-9 && (y - 50.0 * (1.0 - 1.0 / 1.04)).abs() < 1e-9, "{x} {y}");
    }
}
