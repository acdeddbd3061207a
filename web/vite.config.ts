import { defineConfig } from 'vite';
import react from '@vitejs/plugin-react';

// During `npm run dev` the API lives on the C++ server; INCISE_API names it (default: the
// server's default port). The built dashboard is served by that server itself.
const api = process.env.INCISE_API ?? 'http://127.0.0.1:8080';

export default defineConfig({
  plugins: [react()],
  build: { outDir: 'dist', emptyOutDir: true },
  // ws: the live view and replay WebSockets live under /api too.
  server: { proxy: { '/api': { target: api, ws: true } } },
});
