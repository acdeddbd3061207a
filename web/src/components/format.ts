// Number formatting shared by the tables and charts: a few significant digits for small values,
// two decimals for large ones, and the unit after a space.

const large_format = new Intl.NumberFormat(undefined, { maximumFractionDigits: 2 });
const small_format = new Intl.NumberFormat(undefined, { maximumSignificantDigits: 3 });

export function format_value(value: number, unit: string): string {
  const shown = (Math.abs(value) >= 1 ? large_format : small_format).format(value);
  return unit && unit !== 'count' ? `${shown} ${unit}` : shown;
}

/** "12.3 s" for a time into a recording. */
export function format_seconds(t_s: number): string {
  return `${t_s.toFixed(1)} s`;
}
