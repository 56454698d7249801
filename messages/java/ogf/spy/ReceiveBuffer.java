package ogf.spy;

import java.io.IOException;
import java.lang.reflect.Field;
import java.net.MulticastSocket;
import java.nio.file.Files;
import java.nio.file.Paths;
import java.util.ArrayList;
import java.util.List;

/**
 * The kernel receive buffer (SO_RCVBUF) of Java LCM's udpm sockets.
 *
 * Java LCM 1.3.1 (lcm.lcm.UDPMulticastProvider) ignores the URL's recv_buf_size and keeps the kernel's
 * default buffer (net.core.rmem_default, 212992 bytes on Debian), which holds about three 64 KB
 * fragments: a decoded scan is a dozen of them, sent back to back, so nearly every scan loses one and
 * is never delivered. The socket is a package-private field, so it is reached by reflection and
 * enlarged; Linux grants at most net.core.rmem_max.
 */
final class ReceiveBuffer {
  static final int DEFAULT_BYTES = 16 << 20;

  private ReceiveBuffer() {}

  /** recv_buf_size=N of a udpm URL, or -1 when it has none. */
  static int fromUrl(String url) {
    if (url == null) return -1;
    int q = url.indexOf('?');
    if (q < 0) return -1;
    for (String kv : url.substring(q + 1).split("&")) {
      if (kv.startsWith("recv_buf_size=")) {
        try {
          return Integer.parseInt(kv.substring("recv_buf_size=".length()));
        } catch (NumberFormatException e) {
          return -1;
        }
      }
    }
    return -1;
  }

  /** The udpm providers of an LCM instance (lcm.lcm.LCM's package-private `providers`). */
  static List<Object> udpmProviders(lcm.lcm.LCM lcm) throws ReflectiveOperationException {
    Field f = lcm.lcm.LCM.class.getDeclaredField("providers");
    f.setAccessible(true);
    List<Object> out = new ArrayList<>();
    for (Object p : (List<?>) f.get(lcm)) {
      if (p.getClass().getName().equals("lcm.lcm.UDPMulticastProvider")) out.add(p);
    }
    return out;
  }

  /** The udpm provider whose reader thread `t` is, or null when `t` is no such thread. */
  static Object providerOfReader(Thread t) {
    if (!t.getClass().getName().equals("lcm.lcm.UDPMulticastProvider$ReaderThread")) return null;
    try {
      Field outer = t.getClass().getDeclaredField("this$0");
      outer.setAccessible(true);
      return outer.get(t);
    } catch (ReflectiveOperationException e) {
      return null;
    }
  }

  /**
   * Asks for `bytes` on the provider's socket and says on stderr what the kernel granted (and the fix
   * when net.core.rmem_max capped it). Returns the granted size (the JDK reports the size asked for, not the
   * twice as large one Linux's getsockopt reports).
   */
  static int apply(Object provider, int bytes) throws ReflectiveOperationException, IOException {
    Field f = provider.getClass().getDeclaredField("sock");
    f.setAccessible(true);
    MulticastSocket sock = (MulticastSocket) f.get(provider);
    sock.setReceiveBufferSize(bytes);
    int granted = sock.getReceiveBufferSize();
    if (granted < bytes) {
      System.err.printf("ogf-spy: warning: receive buffer %d bytes, less than the %d asked for: the kernel caps it at"
                            + " net.core.rmem_max=%s; large messages will be lost. Fix: sudo sysctl -w"
                            + " net.core.rmem_max=%d%n",
                        granted, bytes, rmemMax(), bytes);
    } else {
      System.err.printf("ogf-spy: receive buffer %d bytes%n", bytes);
    }
    return granted;
  }

  static String rmemMax() {
    // readAllBytes trusts the file's size, which /proc reports as 0: read a line.
    try (java.io.BufferedReader r = Files.newBufferedReader(Paths.get("/proc/sys/net/core/rmem_max"))) {
      String line = r.readLine();
      return line == null ? "?" : line.trim();
    } catch (IOException e) {
      return "?";
    }
  }

  /**
   * Enlarges the socket of the first udpm reader thread as soon as it starts (lcm-spy creates its LCM inside
   * its constructor, out of reach): polls the live threads every 5 ms, for at most `seconds`, on a daemon
   * thread.
   */
  static void watchReaders(int bytes, double seconds) {
    Thread w = new Thread(() -> {
      long end = System.nanoTime() + (long) (seconds * 1e9);
      while (System.nanoTime() < end) {
        for (Thread t : Thread.getAllStackTraces().keySet()) {
          Object p = providerOfReader(t);
          if (p == null) continue;
          try {
            apply(p, bytes);
          } catch (ReflectiveOperationException | IOException e) {
            System.err.println("ogf-spy: cannot enlarge the receive buffer: " + e);
          }
          return;
        }
        try {
          Thread.sleep(5);
        } catch (InterruptedException e) {
          return;
        }
      }
    }, "ogf-spy receive buffer");
    w.setDaemon(true);
    w.start();
  }
}
