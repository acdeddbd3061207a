import { render, screen } from '@testing-library/react';
import userEvent from '@testing-library/user-event';
import { expect, it } from 'vitest';
import { SkipLink } from './header';

it('is reached first by Tab and moves the focus to the main content', async () => {
  render(
    <>
      <SkipLink />
      <nav>
        <a href="/trainee">My training</a>
      </nav>
      <main id="main" tabIndex={-1}>
        <h1>Page</h1>
      </main>
    </>,
  );
  const user = userEvent.setup();
  await user.tab();
  const link = screen.getByRole('link', { name: 'Skip to content' });
  expect(document.activeElement).toBe(link);
  expect(link.getAttribute('href')).toBe('#main');

  await user.keyboard('{Enter}');
  expect(document.activeElement).toBe(screen.getByRole('main'));
});
