//! The integer trapezoidal profile and the follower of spec §6. Exact: 128-bit intermediates,
//! the reference position x (× 65536) is never wrapped.

use super::Profile;

/// The distance of moving `c` now and slowing by `a` each tick until stopped (spec §6, D(c)).
pub fn stopping_distance(c: i128, a: i128) -> i128 {
    if c <= 0 {
        return 0;
    }
    let k = (c - 1) / a;
    (k + 1) * c - a * k * (k + 1) / 2
}

impl Profile {
    /// One tick of the reference generator.
    pub fn advance(&mut self) {
        if !self.active {
            return;
        }
        if self.stopping {
            let u = if self.decel <= 0 {
                0
            } else {
                (self.v.abs() - self.decel).max(0)
            };
            self.v = self.v.signum() * u;
            self.x += i128::from(self.v);
            if self.v == 0 {
                self.active = false;
                self.stopping = false;
            }
            return;
        }
        let target = i128::from(self.end) * 65536;
        let e = target - self.x;
        let s: i128 = if e != 0 {
            e.signum()
        } else if self.v != 0 {
            i128::from(self.v.signum())
        } else {
            1
        };
        let a = i128::from(self.accel);
        let u = s * i128::from(self.v);
        let cap = (u + a).min(i128::from(self.speed).max(u - a));
        let c = if cap <= 0 {
            cap
        } else {
            // The largest c in 0..=cap that can still stop in |e|: D is increasing in c.
            let room = e.abs();
            let (mut lo, mut hi) = (0i128, cap);
            while lo < hi {
                let mid = lo + (hi - lo + 1) / 2;
                if stopping_distance(mid, a) <= room {
                    lo = mid;
                } else {
                    hi = mid - 1;
                }
            }
            lo
        };
        let v = s * c;
        self.v = v.clamp(i128::from(i64::MIN), i128::from(i64::MAX)) as i64;
        self.x += v;
        if self.x == target && self.v == 0 {
            self.active = false;
        }
    }

    /// TPOS: ⌊x / 65536⌋, wrapped to 32 bits.
    pub fn position(&self) -> i32 {
        (self.x >> 16) as i32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Spec §6: the vendor's round-off example, 258 counts at speed 18 and acceleration 4.
    #[test]
    fn the_vendors_258_count_profile_speed_by_speed() {
        let mut p = Profile {
            active: true,
            end: 258,
            speed: 18 << 16,
            accel: 4 << 16,
            ..Profile::default()
        };
        let mut speeds = Vec::new();
        while p.active {
            p.advance();
            speeds.push(p.v as f64 / 65536.0);
        }
        let mut expected = vec![4.0, 8.0, 12.0, 16.0];
        expected.extend([18.0; 10]);
        expected.extend([15.5, 11.5, 7.5, 3.5, 0.0]);
        assert_eq!(speeds, expected);
        assert_eq!(p.x, 258 << 16);
        assert_eq!(p.position(), 258);
    }

    #[test]
    fn stopping_distances() {
        let a = 4 << 16;
        assert_eq!(stopping_distance(0, a), 0);
        // 4 now, then 0: 4 counts.
        assert_eq!(stopping_distance(4 << 16, a), 4 << 16);
        // 18, 14, 10, 6, 2 = 50 counts.
        assert_eq!(stopping_distance(18 << 16, a), 50 << 16);
    }
}
