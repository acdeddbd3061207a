import type { ReactNode } from 'react';

/**
 * A page section titled by its own heading, so that it is a named region (what the browser tests
 * find with getByRole('region', { name })). The heading's id is `${id}-title`, for a table inside
 * the card to be labelled by it.
 */
export function Card({
  id,
  title,
  grow = false,
  children,
}: {
  id: string;
  title: string;
  /** Take the remaining width inside a `.columns` row. */
  grow?: boolean;
  children: ReactNode;
}) {
  const title_id = `${id}-title`;
  return (
    <section className={grow ? 'card grow' : 'card'} aria-labelledby={title_id}>
      <h2 id={title_id}>{title}</h2>
      {children}
    </section>
  );
}
