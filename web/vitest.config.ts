import { defineConfig, mergeConfig } from 'vitest/config';
import vite_config from './vite.config.ts';

// Unit and component tests: src/**/*.test.ts(x) in jsdom. They are not part of the bundle
// (nothing in src/main.tsx imports them); tsc type-checks them with the rest of src/.
export default mergeConfig(
  vite_config,
  defineConfig({
    test: {
      environment: 'jsdom',
      include: ['src/**/*.test.{ts,tsx}'],
      setupFiles: ['src/test_setup.ts'],
    },
  }),
);
