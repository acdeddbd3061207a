// Messages for the person: errors are role="alert" so that they are announced and never missed.

export function ErrorAlert({ message }: { message: string | null }) {
  if (!message) return null;
  return (
    <p role="alert" className="alert alert-error">
      {message}
    </p>
  );
}

export function StatusMessage({ message }: { message: string | null }) {
  if (!message) return null;
  return (
    <p role="status" className="alert alert-success">
      {message}
    </p>
  );
}
