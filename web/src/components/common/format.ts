// Number formatting shared by the tables and charts: a few significant digits for small values,
// two decimals for large ones, and the unit after a space.

const large_format = new Intl.NumberFormat(undefined, { maximumFractionDigits: 2 });
const small_format = new Intl.NumberFormat(undefined, { maximumSignificantDigits: 3 });

/** Units shown at another scale: a cut's area reads better in mm² than in m². */
const display_units: Record<string, { unit: string; scale: number }> = {
  'm^2': { unit: 'mm²', scale: 1e6 },
};

export function format_value(value: number, unit: string): string {
  const display = display_units[unit] ?? { unit, scale: 1 };
  const scaled = value * display.scale;
  const shown = (Math.abs(scaled) >= 1 ? large_format : small_format).format(scaled);
  return display.unit && display.unit !== 'count' ? `${shown} ${display.unit}` : shown;
}

/** "12.3 s" for a time into a recording. */
export function format_seconds(t_s: number): string {
  return `${t_s.toFixed(1)} s`;
}
