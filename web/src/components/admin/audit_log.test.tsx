import { render, screen } from '@testing-library/react';
import { describe, expect, it } from 'vitest';
import type { AuditEntry } from '../../api';
import { AuditChange } from './audit_log';

const entry = (change: Partial<AuditEntry>): AuditEntry => ({
  id: 7,
  at: '2030-01-07T08:00:00Z',
  user_id: 1,
  action: 'station.update',
  detail: 'Station 1',
  before: null,
  after: null,
  ...change,
});

describe('AuditChange', () => {
  it('shows each changed field before and after', () => {
    render(<AuditChange entry={entry({ before: { kind: 'bench', retired: false }, after: { kind: 'laparoscopy', retired: true } })} />);
    const items = screen.getAllByRole('listitem').map((li) => li.textContent);
    expect(items).toEqual(['kind: “bench” → “laparoscopy”', 'retired: false → true']);
  });

  it('lists what a creation created, without a before', () => {
    render(<AuditChange entry={entry({ action: 'station.create', after: { name: 'Bench 5', kind: '' } })} />);
    expect(screen.getAllByRole('listitem').map((li) => li.textContent)).toEqual(['name: “Bench 5”', 'kind: “”']);
  });

  it('cuts a long value short', () => {
    render(<AuditChange entry={entry({ before: { definition: null }, after: { definition: { text: 'x'.repeat(200) } } })} />);
    const text = screen.getByRole('listitem').textContent;
    expect(text.endsWith('…')).toBe(true);
    expect(text.length).toBeLessThan(120);
  });

  it('shows a dash for a change that records no fields', () => {
    const { container } = render(<AuditChange entry={entry({ action: 'export.scores' })} />);
    expect(container.textContent).toBe('—');
  });
});
