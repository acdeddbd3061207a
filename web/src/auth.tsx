// Who is logged in, for every page. The server's session cookie is HttpOnly, so the dashboard
// learns the user from /api/me at start and from /api/login afterwards.
import { useQueryClient } from '@tanstack/react-query';
import { createContext, useCallback, useContext, useEffect, useMemo, useRef, useState, type ReactNode } from 'react';
import { api, ApiError, set_unauthorized_handler, type Role, type User } from './api';
import { navigate } from './router';
import { error_text } from './use_resource';

interface Auth {
  /** undefined while the start-up check runs, null when nobody is logged in. */
  user: User | null | undefined;
  /** Why the person was sent to the login page, if not by their own choice. */
  notice: string | null;
  start_error: string | null;
  logged_in: (user: User) => void;
  log_out: () => Promise<void>;
}

const AuthContext = createContext<Auth | null>(null);

export function home_path(role: Role): string {
  // The administration opens on its first area.
  return role === 'admin' ? '/admin/users' : `/${role}`;
}

export function AuthProvider({ children }: { children: ReactNode }) {
  const [user, set_user] = useState<User | null | undefined>(undefined);
  const [notice, set_notice] = useState<string | null>(null);
  const [start_error, set_start_error] = useState<string | null>(null);
  const user_ref = useRef<User | null | undefined>(undefined);
  useEffect(() => {
    user_ref.current = user;
  }, [user]);
  // Cached answers belong to who asked: none survives a change of user.
  const query_client = useQueryClient();

  useEffect(() => {
    set_unauthorized_handler(() => {
      if (user_ref.current) set_notice('Your session has ended. Please log in again.');
      query_client.clear();
      set_user(null);
      navigate('/login');
    });
    api.me().then(set_user, (reason: unknown) => {
      // 401 (nobody logged in) is handled above; anything else must not pass silently.
      set_user(null);
      if (!(reason instanceof ApiError && reason.status === 401)) {
        set_start_error(`Could not check your login: ${error_text(reason)}`);
      }
    });
  }, [query_client]);

  const logged_in = useCallback(
    (next: User) => {
      query_client.clear();
      set_notice(null);
      set_start_error(null);
      set_user(next);
    },
    [query_client],
  );

  const log_out = useCallback(async () => {
    await api.logout();
    query_client.clear();
    set_notice(null);
    set_user(null);
    navigate('/login');
  }, [query_client]);

  const value = useMemo(
    () => ({ user, notice, start_error, logged_in, log_out }),
    [user, notice, start_error, logged_in, log_out],
  );
  return <AuthContext.Provider value={value}>{children}</AuthContext.Provider>;
}

export function useAuth(): Auth {
  const auth = useContext(AuthContext);
  if (!auth) throw new Error('useAuth outside AuthProvider');
  return auth;
}

/** The logged-in user, for pages that are only rendered for one. */
export function useUser(): User {
  const { user } = useAuth();
  if (!user) throw new Error('useUser without a logged-in user');
  return user;
}
