import type { Material } from '../../api';
import { format_date_time } from '../../time';
import { DataTable } from '../common/data_table';
import { useSceneTitle } from './calibration_jobs';
import { format_kpa, format_misfit, method_label } from './tissue_format';

const nu_format = new Intl.NumberFormat(undefined, { maximumSignificantDigits: 3 });

/** The saved tissue materials with the tasks whose curriculum names each. */
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
          { header: 'Scene', cell: (m) => scene_title(m.scene) },
          { header: 'Model', cell: (m) => m.model },
          { header: 'E', cell: (m) => format_kpa(m.E), className: 'numeric' },
          { header: 'ν', cell: (m) => nu_format.format(m.nu), className: 'numeric' },
          { header: 'Method', cell: (m) => (m.job === null ? method_label(m.method) : `${method_label(m.method)} (run #${m.job})`) },
          { header: 'Misfit', cell: (m) => format_misfit(m.misfit), className: 'numeric' },
          { header: 'Created', cell: (m) => `${m.created_by}, ${format_date_time(m.created_at)}` },
          {
            header: 'Used by',
            cell: (m) => <span data-testid={`material-${m.id}-tasks`}>{m.tasks.length ? m.tasks.join(', ') : '—'}</span>,
          },
        ]}
      />
    </div>
  );
}
