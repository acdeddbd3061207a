import type { Material } from '../../api';
import { format_date_time } from '../../time';
import { DataTable } from '../common/data_table';
import { useSceneTitle } from './calibration_jobs';
import { format_kpa, format_misfit, method_label, scene_file_name } from './tissue_format';

const nu_format = new Intl.NumberFormat(undefined, { maximumSignificantDigits: 3 });

/** A mass-spring material has no Poisson's ratio of its own: its springs fix it. */
function shown_nu(m: Material): string {
  return m.model === 'mss' ? '—' : nu_format.format(m.nu);
}

/**
 * The saved tissue materials with the tasks whose curriculum names each: the scene by its file
 * name and who saved one in tooltips, the constants' headers as written (the table's uppercase
 * would turn ν into N).
 */
export function MaterialsTable({ materials }: { materials: Material[] }) {
  const scene_title = useSceneTitle();
  return (
    <div data-testid="materials">
      <DataTable<Material>
        labelled_by="materials-title"
        rows={materials}
        row_key={(m) => m.id}
        columns={[
          { header: 'Name', cell: (m) => m.name },
          { header: 'Scene', cell: (m) => <span title={scene_title(m.scene)}>{scene_file_name(m.scene)}</span> },
          { header: 'Model', cell: (m) => m.model },
          {
            header: (
              <abbr className="as-written" title="Young's modulus">
                E
              </abbr>
            ),
            cell: (m) => format_kpa(m.E),
            className: 'numeric nowrap',
          },
          {
            header: (
              <abbr className="as-written" title="Poisson's ratio">
                ν
              </abbr>
            ),
            cell: shown_nu,
            className: 'numeric nowrap',
          },
          { header: 'Method', cell: (m) => (m.job === null ? method_label(m.method) : `${method_label(m.method)} (run #${m.job})`) },
          { header: 'Misfit', cell: (m) => format_misfit(m.misfit), className: 'numeric nowrap' },
          {
            header: 'Created',
            cell: (m) => <span title={`Saved by ${m.created_by}`}>{format_date_time(m.created_at)}</span>,
          },
          {
            header: 'Used by',
            cell: (m) => <span data-testid={`material-${m.id}-tasks`}>{m.tasks.length ? m.tasks.join(', ') : '—'}</span>,
          },
        ]}
      />
    </div>
  );
}
