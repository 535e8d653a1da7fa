/* The socket side of dtmap's ONELAB client. Gmsh listens on a Unix socket
 * (a path) or on TCP (host:port) and passes its address after -onelab; each
 * message is two native ints, the type and the body length, then the body.
 * The client announces itself with START (its pid) and leaves with STOP. */
#include <errno.h>
#include <netdb.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#include "dtmap/error.h"
#include "onelab-impl.h"

static int is_unix_address(const char *a) { return strchr(a, '/') || !strchr(a, ':'); }

static int connect_unix(const char *path) {
  struct sockaddr_un addr = {0};
  if (strlen(path) >= sizeof addr.sun_path) return -1;
  int fd = socket(AF_UNIX, SOCK_STREAM, 0);
  if (fd < 0) return -1;
  addr.sun_family = AF_UNIX;
  memcpy(addr.sun_path, path, strlen(path) + 1);
  for (int tries = 0; tries < 5; tries++) {
    if (connect(fd, (struct sockaddr *)&addr, sizeof addr) == 0) return fd;
    nanosleep(&(struct timespec){0, 100000000}, NULL);
  }
  close(fd);
  return -1;
}

static int connect_tcp(const char *address) {
  char host[256];
  const char *colon = strrchr(address, ':');
  snprintf(host, sizeof host, "%.*s", (int)(colon - address), address);
  struct addrinfo hints = {0}, *res = NULL;
  hints.ai_socktype = SOCK_STREAM;
  if (getaddrinfo(host[0] ? host : "localhost", colon + 1, &hints, &res) != 0) return -1;
  int fd = -1;
  for (struct addrinfo *p = res; p && fd < 0; p = p->ai_next) {
    fd = socket(p->ai_family, p->ai_socktype, p->ai_protocol);
    if (fd >= 0 && connect(fd, p->ai_addr, p->ai_addrlen) != 0) close(fd), fd = -1;
  }
  freeaddrinfo(res);
  return fd;
}

/* Write the head and the body with one sendmsg when the socket takes them
 * whole: the supervisor and its worker share the connection, and a message
 * sent in one call is not interleaved with another's. */
static int write_all(int fd, const void *head, size_t nh, const void *body, size_t nb) {
  struct iovec iov[2] = {{(void *)head, nh}, {(void *)body, nb}};
  struct msghdr m = {.msg_iov = iov, .msg_iovlen = nb ? 2 : 1};
  while (m.msg_iovlen) {
    ssize_t k = sendmsg(fd, &m, MSG_NOSIGNAL);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return -1;
    size_t done = (size_t)k;
    while (m.msg_iovlen && done >= m.msg_iov->iov_len) done -= m.msg_iov->iov_len, m.msg_iov++, m.msg_iovlen--;
    if (m.msg_iovlen) m.msg_iov->iov_base = (char *)m.msg_iov->iov_base + done, m.msg_iov->iov_len -= done;
  }
  return 0;
}

static int read_all(int fd, void *buf, size_t n) {
  char *p = buf;
  while (n) {
    ssize_t k = recv(fd, p, n, 0);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return -1;
    p += k, n -= (size_t)k;
  }
  return 0;
}

int dtm_ol_send(ol_conn *c, int type, const char *body, size_t len) {
  int head[2] = {type, (int)len};
  if (c->fd < 0) return DTM_ERR(DTM_ERR_INTERNAL, "ONELAB: not connected");
  if (write_all(c->fd, head, sizeof head, body, len))
    return DTM_ERR(DTM_ERR_INTERNAL, "ONELAB: lost the connection to Gmsh (%s)", strerror(errno));
  return DTM_OK;
}

int dtm_ol_send_text(ol_conn *c, int type, const char *text) { return dtm_ol_send(c, type, text, strlen(text)); }

static int wait_readable(int fd, double seconds) {
  fd_set set;
  FD_ZERO(&set);
  FD_SET(fd, &set);
  struct timeval tv = {(long)seconds, (long)((seconds - (long)seconds) * 1e6)};
  int r;
  do r = select(fd + 1, &set, NULL, NULL, &tv);
  while (r < 0 && errno == EINTR);
  return r;
}

int dtm_ol_recv(ol_conn *c, int *type, char **body, size_t *len) {
  int head[2];
  *body = NULL;
  if (wait_readable(c->fd, c->timeout) <= 0)
    return DTM_ERR(DTM_ERR_INTERNAL, "ONELAB: no reply from Gmsh within %g s", c->timeout);
  if (read_all(c->fd, head, sizeof head) || head[1] < 0)
    return DTM_ERR(DTM_ERR_INTERNAL, "ONELAB: Gmsh closed the connection");
  *body = malloc((size_t)head[1] + 1);
  if (!*body) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (read_all(c->fd, *body, (size_t)head[1])) {
    free(*body), *body = NULL;
    return DTM_ERR(DTM_ERR_INTERNAL, "ONELAB: Gmsh closed the connection in a message");
  }
  (*body)[head[1]] = '\0';
  *type = head[0], *len = (size_t)head[1];
  return DTM_OK;
}

int dtm_ol_connect(ol_conn *c, const char *name, const char *address) {
  char pid[32];
  c->timeout = 300.0;
  snprintf(c->name, sizeof c->name, "%s", name);
  c->fd = is_unix_address(address) ? connect_unix(address) : connect_tcp(address);
  if (c->fd < 0) return DTM_ERR(DTM_ERR_INPUT, "ONELAB: cannot connect to Gmsh at '%s'", address);
  snprintf(pid, sizeof pid, "%ld", (long)getpid());
  return dtm_ol_send_text(c, OL_START, pid);
}

void dtm_ol_close(ol_conn *c) {
  if (c->fd < 0) return;
  dtm_ol_send_text(c, OL_STOP, "Goodbye!");
  close(c->fd);
  c->fd = -1;
}
