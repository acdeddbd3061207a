import { describe, expect, it } from 'vitest';
import { angles_from_quaternion, quaternion_from_angles } from './rotation';

describe('calibration rotation', () => {
  it('is the identity at zero angles', () => {
    expect(quaternion_from_angles({ yaw_deg: 0, pitch_deg: 0, roll_deg: 0 })).toEqual([1, 0, 0, 0]);
  });

  it('turns a quarter about z for a yaw of 90 degrees', () => {
    const [w, x, y, z] = quaternion_from_angles({ yaw_deg: 90, pitch_deg: 0, roll_deg: 0 });
    expect(w).toBeCloseTo(Math.SQRT1_2, 12);
    expect(x).toBeCloseTo(0, 12);
    expect(y).toBeCloseTo(0, 12);
    expect(z).toBeCloseTo(Math.SQRT1_2, 12);
  });

  it('gives back the angles it was made of', () => {
    for (const angles of [
      { yaw_deg: 30, pitch_deg: -20, roll_deg: 45 },
      { yaw_deg: -170, pitch_deg: 60, roll_deg: -90 },
      { yaw_deg: 5, pitch_deg: 0.5, roll_deg: 179 },
    ]) {
      const back = angles_from_quaternion(quaternion_from_angles(angles));
      expect(back.yaw_deg).toBeCloseTo(angles.yaw_deg, 9);
      expect(back.pitch_deg).toBeCloseTo(angles.pitch_deg, 9);
      expect(back.roll_deg).toBeCloseTo(angles.roll_deg, 9);
    }
  });

  it('reads a quaternion that is not quite unit as its direction', () => {
    const back = angles_from_quaternion([2, 0, 0, 0]);
    expect(back).toEqual({ yaw_deg: 0, pitch_deg: 0, roll_deg: 0 });
  });

  it('makes unit quaternions', () => {
    const q = quaternion_from_angles({ yaw_deg: 12, pitch_deg: 34, roll_deg: 56 });
    expect(Math.hypot(...q)).toBeCloseTo(1, 14);
  });
});
