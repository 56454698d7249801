package ogf.spy;

import java.io.DataInput;
import java.io.IOException;
import java.util.Map;
import java.util.TreeMap;

import lcm.lcm.LCM;
import lcm.lcm.LCMDataInputStream;
import lcm.lcm.LCMSubscriber;
import lcm.spy.LCMTypeDatabase;

/**
 * lcm-spy with a receive buffer large enough for ogf's scans (see ReceiveBuffer), or, with --text, the same
 * receive path without a window: every channel's messages, rate and bandwidth each second, as lcm-spy's
 * table shows them, and the totals at exit (Ctrl-C, SIGTERM or --duration).
 *
 *   java -cp lcm.jar:jchart2d.jar:lcmtypes_ogf.jar:ogf_spy.jar ogf.spy.Main
 *        [--lcm-url URL] [--buffer BYTES] [--text [--duration S]]
 *
 * BYTES: the socket receive buffer (default recv_buf_size of the URL, else 16 MiB); 0 keeps Java LCM's own,
 * the kernel default.
 */
public final class Main {
  private Main() {}

  static void usage(int rc) {
    System.err.println("usage: ogf.spy.Main [--lcm-url URL] [--buffer BYTES] [--text [--duration S]]");
    System.exit(rc);
  }

  static void noDisplay(String why) {
    System.err.println("ogf-spy: cannot open lcm-spy's window (" + why + "). Over ssh or on the robot, run "
                       + "scripts/lcm-spy.sh --text (the same table each second, no window), or log in with ssh -X.");
    System.exit(1);
  }

  public static void main(String[] args) throws Exception {
    String url = null;
    int buffer = -1;
    boolean text = false;
    double duration = 0;
    for (int i = 0; i < args.length; ++i) {
      String a = args[i];
      try {
        if (a.equals("-l") || a.equals("--lcm-url")) {
          if (++i >= args.length) usage(2);
          url = args[i];
        } else if (a.startsWith("--lcm-url=")) {
          url = a.substring("--lcm-url=".length());
        } else if (a.equals("--buffer")) {
          if (++i >= args.length) usage(2);
          buffer = Integer.parseInt(args[i]);
        } else if (a.equals("--text")) {
          text = true;
        } else if (a.equals("--duration")) {
          if (++i >= args.length) usage(2);
          duration = Double.parseDouble(args[i]);
        } else if (a.equals("-h") || a.equals("--help")) {
          usage(0);
        } else {
          System.err.println("ogf-spy: unknown option " + a);
          usage(2);
        }
      } catch (NumberFormatException e) {
        System.err.println("ogf-spy: " + a + " needs a number, got " + args[i]);
        usage(2);
      }
    }
    if (url == null || url.isEmpty()) url = System.getenv("LCM_DEFAULT_URL");
    if (url == null || url.isEmpty()) url = "udpm://239.255.76.67:7667";
    if (buffer < 0) buffer = ReceiveBuffer.fromUrl(url);
    if (buffer < 0) buffer = ReceiveBuffer.DEFAULT_BYTES;

    if (!text) {
      // Without a usable display Swing throws HeadlessException or AWTError: say what to do instead.
      if (java.awt.GraphicsEnvironment.isHeadless()) noDisplay("this Java runs headless");
      if (buffer > 0) ReceiveBuffer.watchReaders(buffer, 60);
      try {
        lcm.spy.Spy.main(new String[] {"--lcm-url=" + url});
      } catch (java.awt.HeadlessException | java.awt.AWTError e) {
        noDisplay(e.getMessage());
      }
      return;
    }
    new TextSpy(url, buffer).run(duration);
  }

  /** lcm-spy's receive path and statistics, printed as text. */
  static final class TextSpy implements LCMSubscriber {
    static final class Channel {
      String type = "?";
      long received, lastReceived, undecodable, bytes, lastBytes;
      long firstNanos, lastNanos;
    }

    final Map<String, Channel> channels = new TreeMap<>();
    final LCMTypeDatabase types = new LCMTypeDatabase();
    final LCM lcm;
    final long start = System.nanoTime();

    TextSpy(String url, int buffer) throws Exception {
      lcm = new LCM(url);
      if (buffer > 0) {
        for (Object p : ReceiveBuffer.udpmProviders(lcm)) ReceiveBuffer.apply(p, buffer);
      }
      System.err.println("ogf-spy: listening on " + url);
    }

    // As lcm.spy.Spy.MySubscriber, on LCM's reader thread: look the type up by fingerprint and decode.
    @Override
    public void messageReceived(LCM lcm, String channel, LCMDataInputStream ins) {
      Channel c;
      int size = ins.available();
      synchronized (channels) {
        c = channels.computeIfAbsent(channel, k -> new Channel());
        long now = System.nanoTime();
        if (c.received == 0) c.firstNanos = now;
        c.lastNanos = now;
        c.received++;
        c.bytes += size;
      }
      try {
        long fingerprint = size >= 8 ? ins.readLong() : -1;
        ins.reset();
        Class<?> cls = types.getClassByFingerprint(fingerprint);
        if (cls == null) throw new IOException("unknown type");
        c.type = cls.getSimpleName();
        cls.getConstructor(DataInput.class).newInstance(ins);
      } catch (Exception e) {
        synchronized (channels) {
          c.undecodable++;
        }
      }
    }

    // Every second as lcm-spy's table (messages, Hz and KB/s over the last second); at exit the totals, with
    // the rate between a channel's first and last message.
    void print(String title, double dt, boolean totals) {
      synchronized (printing) {
        // Nothing after the totals: the periodic table may be due while the shutdown hook runs.
        if (finished) return;
        finished = totals;
        printTable(title, dt, totals);
      }
    }

    private final Object printing = new Object();
    private boolean finished = false;

    private void printTable(String title, double dt, boolean totals) {
      StringBuilder s = new StringBuilder(title).append('\n');
      s.append(String.format("%-22s %-22s %10s %9s %12s %11s%n", "channel", "type", "messages", "Hz", "KB/s",
                             "undecodable"));
      synchronized (channels) {
        for (Map.Entry<String, Channel> e : channels.entrySet()) {
          Channel c = e.getValue();
          double hz, kbs;
          if (totals) {
            double span = (c.lastNanos - c.firstNanos) / 1e9;
            hz = span > 0 ? (c.received - 1) / span : 0;
            kbs = span > 0 ? c.bytes / 1024.0 / span : 0;
          } else {
            hz = (c.received - c.lastReceived) / dt;
            kbs = (c.bytes - c.lastBytes) / 1024.0 / dt;
          }
          s.append(String.format("%-22s %-22s %10d %9.2f %12.1f %11d%n", e.getKey(), c.type, c.received, hz, kbs,
                                 c.undecodable));
          c.lastReceived = c.received;
          c.lastBytes = c.bytes;
        }
      }
      System.out.print(s);
      System.out.flush();
    }

    void run(double duration) throws InterruptedException {
      Runtime.getRuntime().addShutdownHook(new Thread(() -> {
        print(String.format("totals over %.1f s", (System.nanoTime() - start) / 1e9), 0, true);
      }));
      lcm.subscribeAll(this);
      long last = System.nanoTime();
      while (duration <= 0 || (System.nanoTime() - start) / 1e9 < duration) {
        Thread.sleep(1000);
        long now = System.nanoTime();
        print(String.format("at %.0f s", (now - start) / 1e9), (now - last) / 1e9, false);
        last = now;
      }
      System.exit(0);
    }
  }
}
