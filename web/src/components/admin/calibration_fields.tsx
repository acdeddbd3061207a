import { angles_from_quaternion, quaternion_from_angles, type Angles } from './rotation';

// The calibration's JSON (docs/api.md "Calibration") as the form reads it; fields it does not
// show (a scope's portal, its limits) are kept as they are.
interface Mapping {
  scale?: number;
  rotation?: number[];
  offset?: number[];
  [key: string]: unknown;
}
interface DeviceCalibration {
  index?: number;
  kind?: string;
  mapping?: Mapping;
  [key: string]: unknown;
}
interface Calibration {
  devices?: DeviceCalibration[];
  [key: string]: unknown;
}

function parse(text: string): Calibration | null {
  try {
    const value: unknown = JSON.parse(text);
    if (!value || typeof value !== 'object' || Array.isArray(value)) return null;
    const calibration = value as Calibration;
    return Array.isArray(calibration.devices) ? calibration : null;
  } catch {
    return null;
  }
}

/** A number field; an empty or unreadable entry leaves the value as it was. */
function NumberField({ id, label, value, step, on_change }: { id: string; label: string; value: number; step: number; on_change: (v: number) => void }) {
  return (
    <span className="number-field">
      <label htmlFor={id}>{label}</label>
      <input
        id={id}
        type="number"
        step={step}
        value={Number(value.toFixed(6))}
        onChange={(e) => {
          const v = Number(e.target.value);
          if (e.target.value !== '' && Number.isFinite(v)) on_change(v);
        }}
      />
    </span>
  );
}

/**
 * Each device's mapping as fields: its kind, scale, rotation as yaw, pitch and roll in degrees, and
 * offset in millimetres. It edits the same JSON text the power users' box shows; the server
 * validates what is saved.
 */
export function CalibrationFields({ text, disabled, on_change }: { text: string; disabled: boolean; on_change: (text: string) => void }) {
  const calibration = parse(text);
  if (!calibration) {
    return <p className="hint">The JSON below is not a calibration the form can read; fix it there, or reload.</p>;
  }
  const devices = calibration.devices ?? [];

  function update(i: number, change: (device: DeviceCalibration) => DeviceCalibration) {
    const next = { ...calibration, devices: devices.map((d, j) => (j === i ? change(d) : d)) };
    on_change(JSON.stringify(next, null, 2));
  }
  function set_mapping(i: number, change: Partial<Mapping>) {
    update(i, (d) => ({ ...d, mapping: { ...d.mapping, ...change } }));
  }

  return (
    <fieldset className="calibration-fields" disabled={disabled}>
      <legend>Devices</legend>
      {devices.map((device, i) => {
        const mapping = device.mapping ?? {};
        const angles = angles_from_quaternion(mapping.rotation ?? [1, 0, 0, 0]);
        const offset = mapping.offset ?? [0, 0, 0];
        const set_angle = (key: keyof Angles, v: number) =>
          set_mapping(i, { rotation: quaternion_from_angles({ ...angles, [key]: v }) });
        const id = `calibration-${i}`;
        return (
          <div key={i} className="calibration-device" data-testid={`calibration-device-${i}`}>
            <h3>Device {(device.index ?? i) + 1}</h3>
            <span className="number-field">
              <label htmlFor={`${id}-kind`}>Kind</label>
              <select id={`${id}-kind`} value={device.kind ?? 'pen'} onChange={(e) => update(i, (d) => ({ ...d, kind: e.target.value }))}>
                <option value="pen">Pen</option>
                <option value="scope">Scope</option>
              </select>
            </span>
            <NumberField id={`${id}-scale`} label="Scale" step={0.01} value={mapping.scale ?? 1} on_change={(v) => set_mapping(i, { scale: v })} />
            <NumberField id={`${id}-yaw`} label="Yaw (°)" step={1} value={angles.yaw_deg} on_change={(v) => set_angle('yaw_deg', v)} />
            <NumberField id={`${id}-pitch`} label="Pitch (°)" step={1} value={angles.pitch_deg} on_change={(v) => set_angle('pitch_deg', v)} />
            <NumberField id={`${id}-roll`} label="Roll (°)" step={1} value={angles.roll_deg} on_change={(v) => set_angle('roll_deg', v)} />
            {(['x', 'y', 'z'] as const).map((axis, k) => (
              <NumberField
                key={axis}
                id={`${id}-offset-${axis}`}
                label={`Offset ${axis} (mm)`}
                step={0.5}
                value={(offset[k] ?? 0) * 1000}
                on_change={(v) => set_mapping(i, { offset: offset.map((o, m) => (m === k ? v / 1000 : o)) })}
              />
            ))}
          </div>
        );
      })}
    </fieldset>
  );
}
