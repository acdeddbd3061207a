import { useState } from 'react';

import { api, ApiError, type CurriculumEntry } from '../../api';
import { from_display, metric_name, to_display, useMetricCatalogue } from '../../metrics';

/**
 * The pass thresholds of a curriculum's tasks, editable: one number per metric a task scores,
 * entered in the unit the dashboard shows it in (a cut's area in mm², a share in %), and stored
 * in the metric's own unit. Saving sends the whole definition back (PUT /api/curricula/{id}); the
 * server validates it (against the metric's range too) and answers with the first problem.
 */
export function ThresholdEditor({ curriculum, on_saved }: { curriculum: CurriculumEntry; on_saved: () => void }) {
  // Edited values by "task/metric", as typed.
  const [edits, set_edits] = useState<Record<string, string>>({});
  const [message, set_message] = useState<{ ok: boolean; text: string } | null>(null);
  const [busy, set_busy] = useState(false);
  const catalogue = useMetricCatalogue();

  const save = async () => {
    const definition = structuredClone(curriculum.definition);
    for (const module of definition.modules) {
      for (const task of module.tasks) {
        for (const metric of task.metrics ?? []) {
          const typed = edits[`${task.key}/${metric.key}`];
          if (typed !== undefined) metric.threshold.value = from_display(catalogue?.get(metric.key), Number(typed));
        }
      }
    }
    set_busy(true);
    try {
      await api.update_curriculum(curriculum.id, definition);
      set_message({ ok: true, text: 'Thresholds saved.' });
      set_edits({});
      on_saved();
    } catch (error) {
      set_message({ ok: false, text: error instanceof ApiError ? error.message : String(error) });
    } finally {
      set_busy(false);
    }
  };

  return (
    <form
      aria-label="Pass thresholds"
      onSubmit={(e) => {
        e.preventDefault();
        void save();
      }}
    >
      {curriculum.definition.modules.flatMap((module) =>
        module.tasks.map((task) => (
          <fieldset key={task.key}>
            <legend>{task.name}</legend>
            {(task.metrics ?? []).map((metric) => {
              const id = `threshold-${task.key}-${metric.key}`;
              const key = `${task.key}/${metric.key}`;
              const info = catalogue?.get(metric.key);
              const bound = metric.threshold.op === '<=' ? 'at most' : 'at least';
              return (
                <div key={metric.key} className="field">
                  <label htmlFor={id} title={metric.key}>{`${metric_name(catalogue, metric.key)} ${bound}`}</label>
                  <input
                    id={id}
                    type="number"
                    step="any"
                    required
                    value={edits[key] ?? String(to_display(info, metric.threshold.value))}
                    onChange={(e) => set_edits({ ...edits, [key]: e.target.value })}
                  />
                  <span>{info ? info.display_unit : metric.unit}</span>
                </div>
              );
            })}
          </fieldset>
        )),
      )}
      {message && (
        <p role={message.ok ? 'status' : 'alert'} className={message.ok ? 'ok' : undefined}>
          {message.text}
        </p>
      )}
      <button type="submit" className="button-primary" disabled={busy}>
        Save thresholds
      </button>
    </form>
  );
}
