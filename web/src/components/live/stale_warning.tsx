import type { StreamMetrics } from '../../stream';

/** A picture that stands still longer than this while the session runs is called stale. */
export const kStalePictureS = 2;

/**
 * What the trainee must not miss while a session claims to run: a picture that stands still (the
 * stream or the renderer stalled), a simulation behind real time (the server's pace monitor says
 * so and by how much), and a tool whose force model is stale at the station (the
 * agent's watchdog has faded its force out). The server pauses the session itself when a model
 * goes stale; the reason then shows as the session's state.
 */
export function StaleWarning({ metrics, picture_age_s }: { metrics: StreamMetrics | null; picture_age_s: number | null }) {
  if (!metrics || metrics.state !== 'running') return null;
  const lines: string[] = [];
  if (picture_age_s !== null && picture_age_s > kStalePictureS) {
    lines.push(`The picture has not changed for ${Math.floor(picture_age_s)} s.`);
  }
  if (metrics.behind_real_time) {
    const lag = metrics.lag_ms !== undefined ? `${metrics.lag_ms.toFixed(0)} ms` : 'some time';
    const factor = metrics.real_time_factor !== undefined ? ` (${metrics.real_time_factor.toFixed(2)}× real time)` : '';
    lines.push(`The simulation is ${lag} behind real time${factor}.`);
  }
  for (const device of metrics.link?.devices ?? []) {
    if (device.fault === 'stale model') {
      lines.push(
        `Tool ${device.index + 1} has a stale force model (${device.model_age_ms.toFixed(0)} ms old): ` +
          'the station renders no force for it.',
      );
    }
  }
  if (lines.length === 0) return null;
  return (
    <div role="alert" className="alert alert-warning" data-testid="stale-warning">
      {lines.map((line) => (
        <p key={line}>{line}</p>
      ))}
    </div>
  );
}
