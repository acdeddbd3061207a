import type { Role } from '../api';

export interface PageInfo {
  path: string;
  title: string;
  roles: Role[];
}

// Admins see everything instructors see; the server enforces the same rules (403 otherwise).
export const pages: PageInfo[] = [
  { path: '/trainee', title: 'My training', roles: ['trainee'] },
  { path: '/admin', title: 'Administration', roles: ['admin'] },
  { path: '/instructor', title: 'Sessions & bookings', roles: ['instructor', 'admin'] },
];

export function pages_for(role: Role): PageInfo[] {
  return pages.filter((page) => page.roles.includes(role));
}

export function role_label(role: Role): string {
  return { trainee: 'Trainee', instructor: 'Instructor', admin: 'Admin' }[role];
}
