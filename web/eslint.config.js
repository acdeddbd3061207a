// ESLint for the dashboard: typescript-eslint's type-aware rules and React's rules of hooks.
// `npm run lint` allows no warnings. typescript-eslint reads the types through the JS compiler
// API, which is why package.json maps `typescript` to TypeScript 6 while `tsc` is TypeScript 7.
import js from '@eslint/js';
import react_hooks from 'eslint-plugin-react-hooks';
import globals from 'globals';
import tseslint from 'typescript-eslint';

export default tseslint.config(
  { ignores: ['dist/', 'node_modules/'] },
  js.configs.recommended,
  {
    files: ['src/**/*.{ts,tsx}'],
    extends: [...tseslint.configs.strictTypeChecked],
    languageOptions: {
      globals: globals.browser,
      parserOptions: { projectService: true, tsconfigRootDir: import.meta.dirname },
    },
    plugins: { 'react-hooks': react_hooks },
    rules: {
      ...react_hooks.configs.recommended.rules,
      // `onClick={() => set_open(false)}` is how handlers are written here; the value is ignored.
      '@typescript-eslint/no-confusing-void-expression': 'off',
      // Numbers in template strings are how every label here is written.
      '@typescript-eslint/restrict-template-expressions': ['error', { allowNumber: true }],
      // Event handlers passed to JSX may return promises; React ignores the value.
      '@typescript-eslint/no-misused-promises': ['error', { checksVoidReturn: { attributes: false } }],
    },
  },
  {
    files: ['*.{js,ts}', 'vite.config.ts', 'vitest.config.ts'],
    extends: [...tseslint.configs.recommended],
    languageOptions: { globals: globals.node },
  },
);
