import type { CalibratedValue, CalibrationPer } from '../../api';
import { DataTable } from '../common/data_table';
import { format_constant, format_kpa, format_spread, parameter_label, spread_summary } from './tissue_format';

/** A per-node fit has a modulus per node: the table shows this many, the summary covers all. */
export const shown_node_values = 20;

/**
 * The fitted constants, each named by its label or node ("E, label 0", the raw name "E[0]" in a
 * tooltip): the scene's value, the calibrated one (E in kPa, nu as it is) and its spread in per
 * cent of it. Fitted per node, the first few nodes and the smallest, median and largest modulus.
 */
export function CalibratedValues({
  values,
  per,
  node_moduli,
}: {
  values: CalibratedValue[];
  per: CalibrationPer;
  /** Per node [Pa]; the values' own when absent. */
  node_moduli: number[] | undefined;
}) {
  const per_node = per === 'node';
  const shown = per_node ? values.slice(0, shown_node_values) : values;
  const moduli = node_moduli ?? values.filter((v) => v.name.startsWith('E')).map((v) => v.value);
  const summary = per_node && moduli.length > 0 ? spread_summary(moduli) : null;
  return (
    <div data-testid="calibration-values">
      <DataTable<CalibratedValue>
        labelled_by="calibration-values-title"
        rows={shown}
        row_key={(v) => v.name}
        columns={[
          { header: 'Parameter', cell: (v) => <span title={v.name}>{parameter_label(v, per)}</span> },
          { header: 'Start', cell: (v) => format_constant(v.name, v.start), className: 'numeric nowrap' },
          { header: 'Calibrated', cell: (v) => format_constant(v.name, v.value), className: 'numeric nowrap' },
          {
            header: <span title="The search's uncertainty of the value, in per cent of it">Spread</span>,
            cell: (v) => format_spread(v.name, v.spread, v.value),
            className: 'numeric nowrap',
          },
        ]}
      />
      {summary && (
        <p data-testid="node-moduli-summary">
          {(values.length > shown.length ? `The first ${shown.length} of ${values.length} values. ` : '') +
            `Node moduli (${moduli.length} nodes): min ${format_kpa(summary.min)}, ` +
            `median ${format_kpa(summary.median)}, max ${format_kpa(summary.max)}.`}
        </p>
      )}
    </div>
  );
}
