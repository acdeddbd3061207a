// A calibration's rotation is a unit quaternion [w, x, y, z] (devices/kinematics.h); people set it
// as three angles in degrees: yaw about z, then pitch about y, then roll about x (q = qz qy qx).

export interface Angles {
  yaw_deg: number;
  pitch_deg: number;
  roll_deg: number;
}

const kDeg = Math.PI / 180;

export function quaternion_from_angles({ yaw_deg, pitch_deg, roll_deg }: Angles): [number, number, number, number] {
  const [cy, sy] = [Math.cos((yaw_deg * kDeg) / 2), Math.sin((yaw_deg * kDeg) / 2)];
  const [cp, sp] = [Math.cos((pitch_deg * kDeg) / 2), Math.sin((pitch_deg * kDeg) / 2)];
  const [cr, sr] = [Math.cos((roll_deg * kDeg) / 2), Math.sin((roll_deg * kDeg) / 2)];
  return [
    cr * cp * cy + sr * sp * sy,
    sr * cp * cy - cr * sp * sy,
    cr * sp * cy + sr * cp * sy,
    cr * cp * sy - sr * sp * cy,
  ];
}

/** The angles of a quaternion (normalised first); pitch is clamped to ±90° at the poles. */
export function angles_from_quaternion(q: readonly number[]): Angles {
  const norm = Math.hypot(q[0] ?? 1, q[1] ?? 0, q[2] ?? 0, q[3] ?? 0) || 1;
  const [w, x, y, z] = [(q[0] ?? 1) / norm, (q[1] ?? 0) / norm, (q[2] ?? 0) / norm, (q[3] ?? 0) / norm];
  const sin_pitch = Math.max(-1, Math.min(1, 2 * (w * y - z * x)));
  return {
    yaw_deg: Math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)) / kDeg,
    pitch_deg: Math.asin(sin_pitch) / kDeg,
    roll_deg: Math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)) / kDeg,
  };
}
